//! The radial-dexel stock: `r(theta, z)` on a regular grid, outer and inner surface.
//!
//! Each dexel is one sample of a surface radius at the angle `theta_i = theta0 + i*dtheta`
//! and the axial position `z_j = z0 + j*dz` (cell centres). Columns (all z of one angle)
//! are contiguous, so the sweep works on one column at a time and vectorises over z.
//! Radii are handled as *signed radii* `q`: `q = r` for the outer surface and `q = -r` for
//! the inner one, so that cutting always *lowers* `q` (`q = min(q, ..)`). The grid stores
//! `q - q_blank` as `f32`: the blank is all zeros, so its memory comes zeroed from the
//! allocator without being touched (a 3600 x 10000 grid costs no time until it is cut),
//! and the stored values keep f32 precision relative to the blank (sub-nanometre).
//!
//! **One tie rule.** Every profile on a column (a tool's cut, the ideal thread) is taken
//! *right-continuous* in z: a cell whose centre lies exactly on a vertical wall takes the
//! value on the wall's +z side. A cut `[a, b]` therefore covers the cells with
//! `a <= z < b`, and the ideal's walls split cells the same way ([`first_cell`]), so a
//! clean cut of a wall that falls on a cell centre compares and measures exactly.

use std::f64::consts::TAU;

/// The index of the first cell at or after position `x`, given in cells from cell 0:
/// `ceil(x)`, except that a position within 1e-6 of a cell (rounding of the same exact
/// value computed two ways) counts as on it. Every wall is placed on cells by this one rule
/// (see the module docs).
pub(crate) fn first_cell(x: f64) -> f64 {
    let r = x.round();
    if (x - r).abs() <= 1e-6 {
        r
    } else {
        x.ceil()
    }
}

/// The sampling grid.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Grid {
    /// Number of angular columns.
    pub n_theta: usize,
    /// Number of axial cells per column.
    pub n_z: usize,
    /// Angle of column 0 (rad).
    pub theta0: f64,
    /// z of the first cell centre (mm).
    pub z0: f64,
    /// Axial spacing (mm).
    pub dz: f64,
}

impl Grid {
    /// Angle of column `i`.
    pub fn theta(&self, i: usize) -> f64 {
        self.theta0 + self.dtheta() * i as f64
    }

    /// Angular spacing (rad).
    pub fn dtheta(&self) -> f64 {
        TAU / self.n_theta as f64
    }

    /// z of cell `j`.
    pub fn z(&self, j: usize) -> f64 {
        self.z0 + self.dz * j as f64
    }

    /// Dexels per surface.
    pub fn dexels(&self) -> usize {
        self.n_theta * self.n_z
    }

    /// The axial span of the cells (mm): the comparison's window.
    pub fn window(&self) -> (f64, f64) {
        (
            self.z(0) - 0.5 * self.dz,
            self.z(self.n_z.saturating_sub(1)) + 0.5 * self.dz,
        )
    }
}

/// Which surface of the stock.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Surface {
    /// The outside of the bar.
    Outer,
    /// The bore.
    Inner,
}

impl Surface {
    /// Sign of the stored value: `q = sense * r`.
    pub fn sense(self) -> f64 {
        match self {
            Surface::Outer => 1.0,
            Surface::Inner => -1.0,
        }
    }
}

/// A zeroed buffer whose pages the kernel may back with transparent huge pages: the first
/// touch of a 150 MB grid then costs about 70 page faults instead of 37000 (0.25 s on two
/// cores, measured on the seed 002 scene).
/// `None` when the memory cannot be had (the caller reports it; nothing aborts).
fn try_zeroed(n: usize) -> Option<Vec<f32>> {
    if n == 0 {
        return Some(Vec::new());
    }
    let layout = std::alloc::Layout::array::<f32>(n).ok()?;
    // SAFETY: the layout has a nonzero size; a non-null result is a zeroed block of `n`
    // f32 (all-zero bits are 0.0) allocated by the global allocator with the layout `Vec`
    // uses for a capacity of `n`, so the `Vec` owns and frees it correctly.
    let v = unsafe {
        let p = std::alloc::alloc_zeroed(layout).cast::<f32>();
        if p.is_null() {
            return None;
        }
        Vec::from_raw_parts(p, n, n)
    };
    #[cfg(target_os = "linux")]
    {
        const HUGE: usize = 2 << 20;
        let start = v.as_ptr() as usize;
        let end = start + n * std::mem::size_of::<f32>();
        let a = start.next_multiple_of(HUGE);
        let b = end / HUGE * HUGE;
        if b > a {
            // SAFETY: [a, b) lies inside the allocation owned by `v`; MADV_HUGEPAGE only
            // changes how the kernel backs those pages, never their contents.
            unsafe {
                libc::madvise(a as *mut libc::c_void, b - a, libc::MADV_HUGEPAGE);
            }
        }
    }
    Some(v)
}

/// The stock: the blank's surfaces as radial dexels.
#[derive(Clone, Debug)]
pub struct Stock {
    /// The grid.
    pub grid: Grid,
    /// Outer surface, `q - q_blank` with `q = r`, column-major.
    pub outer: Vec<f32>,
    /// Inner surface, `q - q_blank` with `q = -r`, present for a tube.
    pub inner: Option<Vec<f32>>,
    /// Blank outer radius.
    pub blank_outer: f64,
    /// Blank bore radius (0 = solid).
    pub blank_inner: f64,
}

impl Stock {
    /// A blank: a bar (or tube) of the given radii over the grid.
    ///
    /// # Panics
    /// When the memory for the grid cannot be allocated; [`Stock::try_blank`] says so
    /// instead.
    pub fn blank(grid: Grid, outer_radius: f64, bore_radius: f64) -> Stock {
        Stock::try_blank(grid, outer_radius, bore_radius)
            .expect("memory for the stock grid (use Stock::try_blank to handle its absence)")
    }

    /// A blank as [`Stock::blank`] makes it, or `None` when the memory for its grid cannot
    /// be allocated.
    pub fn try_blank(grid: Grid, outer_radius: f64, bore_radius: f64) -> Option<Stock> {
        let n = grid.n_theta.checked_mul(grid.n_z)?;
        Some(Stock {
            grid,
            outer: try_zeroed(n)?,
            inner: if bore_radius > 0.0 {
                Some(try_zeroed(n)?)
            } else {
                None
            },
            blank_outer: outer_radius,
            blank_inner: bore_radius,
        })
    }

    /// Number of stored dexels (both surfaces).
    pub fn stored_dexels(&self) -> usize {
        self.outer.len() + self.inner.as_ref().map_or(0, Vec::len)
    }

    /// Stored values (`q - q_blank`) of one surface, column-major, if the stock has it.
    pub fn surface(&self, s: Surface) -> Option<&[f32]> {
        match s {
            Surface::Outer => Some(&self.outer),
            Surface::Inner => self.inner.as_deref(),
        }
    }

    /// Mutable stored values of one surface.
    pub fn surface_mut(&mut self, s: Surface) -> Option<&mut [f32]> {
        match s {
            Surface::Outer => Some(&mut self.outer),
            Surface::Inner => self.inner.as_deref_mut(),
        }
    }

    /// The initial signed radius of a surface.
    pub fn blank_q(&self, s: Surface) -> f64 {
        match s {
            Surface::Outer => self.blank_outer,
            Surface::Inner => -self.blank_inner,
        }
    }

    /// Radius of a surface at column `i`, cell `j`.
    pub fn radius(&self, s: Surface, i: usize, j: usize) -> Option<f64> {
        let q0 = self.blank_q(s);
        self.surface(s)
            .map(|q| s.sense() * (q[i * self.grid.n_z + j] as f64 + q0))
    }
}

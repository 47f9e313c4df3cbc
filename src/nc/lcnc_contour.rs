//! LinuxCNC's lathe cycles G70 (finishing) and G71/G72 (roughing, `.1` without pockets,
//! `.2` from the first pocket on) as plane geometry: the moves rs274 2.9.0~pre1 makes for a
//! contour, in program units.
//!
//! The semantics are rs274's (LinuxCNC 2.9 G-code manual, "G70", "G71 G72"; behaviour
//! checked move for move against Debian 12's `rs274` in `tests/integration/linuxcnc.rs`).
//! Points are complex numbers `z + i x` (x a radius), as rs274 keeps them, so every
//! tolerance and every rounding step is the control's:
//!
//! - The contour is the lead-in from the cycle's start point to the subroutine's first
//!   point, then its straight and circular segments, with a fillet (`A`) or chamfer (`C`)
//!   segment after a block that asks for one.
//! - It is brought to a normal frame where the passes run towards -z and the depth grows
//!   towards -x: G72 first turns it by -90 deg, then x and z are mirrored as needed (the
//!   inverse transform is applied to every move made). In that frame every segment must
//!   advance towards -z (a straight by at most 1e-3 backwards; an arc lies on the upper half
//!   of its circle counterclockwise or the lower half clockwise and advances by 1e-3):
//!   else "Not monotonic".
//! - Fillets and chamfers: both neighbours are offset by the radius (to the side where their
//!   offset ends overlap), intersected, and the corner point's feet on the neighbours
//!   become the ends of the fillet arc (or the chamfer line).
//! - The allowance `D` offsets the contour (lead-in left out) in steps of at most half its
//!   shortest segment (chord or radius for an arc): each step offsets every segment, drops
//!   those shorter than 1e-3, joins gaps of more than 1e-2 with an arc about the old
//!   corner, drops a segment that turned back (the shorter of it and the one before), and
//!   intersects neighbours; at the end, neighbours meet at their ends' midpoint.
//! - G71/G72 cut layers `I` apart from the start point's depth: in each layer a feed along
//!   the pass axis to where it meets the contour, a 45 deg retract by `R` (less when the cut
//!   is shorter than 2 R), a rapid back and down to the layer; at the contour's end of each
//!   layer the tool follows the contour up to the next layer. Where the contour climbs
//!   again (a pocket) the cut goes on in that pocket from the point it climbed to
//!   (G71/G72), or only the contour is followed (G7x.1), or the first layer is skipped and
//!   the pockets are cut after (G7x.2).
//! - G70 follows the contour offset by `(pass - 1) (D - E) / P + E` for pass = P..1, a
//!   rapid to the start point and to the offset contour's start before each.
//!
//! Errors are rs274's texts (the caller prefixes "G7X error: "). Where rs274 would loop for
//! ever or read past its list, an error says so instead.

use std::ops::{Add, Div, Mul, Neg, Sub};

/// rs274's `tolerance` in interp_g7x.
const TOL: f64 = 1e-6;

/// A point or vector `z + i x` in program units (x a radius).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct C {
    pub(super) re: f64,
    pub(super) im: f64,
}

pub(super) const fn c(re: f64, im: f64) -> C {
    C { re, im }
}

impl C {
    fn conj(self) -> C {
        c(self.re, -self.im)
    }
    fn abs(self) -> f64 {
        self.re.hypot(self.im)
    }
    pub(super) fn norm(self) -> f64 {
        self.re * self.re + self.im * self.im
    }
    /// `i z`.
    fn times_i(self) -> C {
        c(0.0, 1.0) * self
    }
}

impl Add for C {
    type Output = C;
    fn add(self, o: C) -> C {
        c(self.re + o.re, self.im + o.im)
    }
}
impl Sub for C {
    type Output = C;
    fn sub(self, o: C) -> C {
        c(self.re - o.re, self.im - o.im)
    }
}
impl Neg for C {
    type Output = C;
    fn neg(self) -> C {
        c(-self.re, -self.im)
    }
}
impl Mul for C {
    type Output = C;
    fn mul(self, o: C) -> C {
        c(
            self.re * o.re - self.im * o.im,
            self.re * o.im + self.im * o.re,
        )
    }
}
impl Mul<f64> for C {
    type Output = C;
    fn mul(self, t: f64) -> C {
        c(self.re * t, self.im * t)
    }
}
impl Div<f64> for C {
    type Output = C;
    fn div(self, t: f64) -> C {
        c(self.re / t, self.im / t)
    }
}
impl Div for C {
    type Output = C;
    /// Smith's division, the order of operations of the C runtime's complex division, so
    /// results are bit for bit the control's.
    fn div(self, o: C) -> C {
        let (a, b, cc, d) = (self.re, self.im, o.re, o.im);
        if cc.abs() < d.abs() {
            let ratio = cc / d;
            let denom = cc * ratio + d;
            c((a * ratio + b) / denom, (b * ratio - a) / denom)
        } else {
            let ratio = d / cc;
            let denom = d * ratio + cc;
            c((b * ratio + a) / denom, (b - a * ratio) / denom)
        }
    }
}

/// `x + 0i` divided by `z`.
fn real_over(x: f64, z: C) -> C {
    c(x, 0.0) / z
}

/// A move of the cycle, in the program's frame (program units, x a radius).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Out {
    Rapid(C),
    Feed(C),
    /// An arc to `end` about `centre`, counterclockwise (G3) or clockwise (G2) as seen with
    /// z to the right and x up.
    Arc {
        ccw: bool,
        centre: C,
        end: C,
    },
}

/// What a segment is.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Kind {
    Line,
    Arc { ccw: bool, centre: C },
}

/// A corner a block asks for at its end (`A` fillet, `C` chamfer), before it is made.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Corner {
    None,
    Fillet,
    Chamfer,
}

/// One segment of the contour.
#[derive(Clone, Debug)]
pub(super) struct Seg {
    s: C,
    e: C,
    kind: Kind,
    /// A corner's size until it is made (then 0 for a fillet, as rs274 keeps it).
    finish: f64,
    corner: Corner,
}

impl Seg {
    pub(super) fn line(s: C, e: C) -> Seg {
        Seg {
            s,
            e,
            kind: Kind::Line,
            finish: 0.0,
            corner: Corner::None,
        }
    }
    pub(super) fn arc(ccw: bool, s: C, centre: C, e: C) -> Seg {
        Seg {
            s,
            e,
            kind: Kind::Arc { ccw, centre },
            finish: 0.0,
            corner: Corner::None,
        }
    }
    /// A fillet of radius `r` at `at` (made by `Contour::finish_corners`).
    pub(super) fn fillet(r: f64, at: C) -> Seg {
        Seg {
            s: at,
            e: at,
            kind: Kind::Arc {
                ccw: false,
                centre: at,
            },
            finish: r,
            corner: Corner::Fillet,
        }
    }
    /// A chamfer as wide as a fillet of radius `r` at `at`.
    pub(super) fn chamfer(r: f64, at: C) -> Seg {
        Seg {
            s: at,
            e: at,
            kind: Kind::Line,
            finish: r,
            corner: Corner::Chamfer,
        }
    }

    /// The points on the segment at depth `x`: their z values (a horizontal straight gives
    /// both its ends).
    fn at_depth(&self, x: f64) -> Vec<f64> {
        let (s, e) = (self.s, self.e);
        let mut out = Vec::new();
        match self.kind {
            Kind::Line => {
                if s.im.min(e.im) > x + TOL || s.im.max(e.im) < x - TOL {
                    return out;
                }
                if (s.im - e.im).abs() < TOL {
                    out.push(s.re);
                    out.push(e.re);
                } else {
                    out.push((x - s.im) / (e.im - s.im) * (e.re - s.re) + s.re);
                }
            }
            Kind::Arc { centre, .. } => {
                let r = (s - centre).abs();
                let mut q = -(x - r - centre.im) * (x + r - centre.im);
                if q < -TOL {
                    return out;
                }
                if q < 0.0 {
                    q = 0.0;
                }
                let q = q.sqrt();
                for p in [c(centre.re + q, x), c(centre.re - q, x)] {
                    if self.on_arc(p) {
                        out.push(p.re);
                    }
                }
            }
        }
        out
    }

    /// Whether `p` (on the circle) lies between the arc's ends.
    fn on_arc(&self, p: C) -> bool {
        let Kind::Arc { ccw, centre } = self.kind else {
            return false;
        };
        let cross = |a: C| (a.conj() * (p - centre)).im;
        let (a, b) = (cross(self.s - centre), cross(self.e - centre));
        if ccw {
            a >= -TOL && b <= TOL
        } else {
            a <= TOL && b >= -TOL
        }
    }

    fn offset(&mut self, d: f64) {
        match self.kind {
            Kind::Line => {
                let v = c(0.0, d) * (self.s - self.e) / (self.s - self.e).abs();
                self.s = self.s + v;
                self.e = self.e + v;
            }
            Kind::Arc { ccw, centre } => {
                let r = (self.s - centre).abs();
                let f = (r + if ccw { d } else { -d }) / r;
                self.s = (self.s - centre) * f + centre;
                self.e = (self.e - centre) * f + centre;
            }
        }
    }

    /// Its length for the offset steps: a straight's length, an arc's chord or radius
    /// (the smaller).
    fn size(&self) -> f64 {
        match self.kind {
            Kind::Line => (self.s - self.e).abs(),
            Kind::Arc { centre, .. } => (self.s - self.e).abs().min((self.s - centre).abs()),
        }
    }

    fn monotonic(&self) -> bool {
        match self.kind {
            Kind::Line => (self.e - self.s).re <= 1e-3,
            Kind::Arc { ccw, centre } => {
                if self.finish != 0.0 {
                    return true;
                }
                let entry = (self.s - centre).im;
                let exit = (self.e - centre).im;
                let dz = (self.e - self.s).re;
                if ccw {
                    entry >= -1e-3 && exit >= -1e-3 && dz <= -1e-3
                } else {
                    entry <= 1e-3 && exit <= 1e-3 && dz <= -1e-3
                }
            }
        }
    }

    /// Apply a map of the plane to the ends (and centre); `mirror` reverses arcs.
    fn map(&mut self, f: impl Fn(C) -> C, mirror: bool) {
        self.s = f(self.s);
        self.e = f(self.e);
        if let Kind::Arc { ccw, centre } = self.kind {
            self.kind = Kind::Arc {
                ccw: ccw != mirror,
                centre: f(centre),
            };
        }
    }

    fn draw(&self, out: &mut Vec<Out>) {
        out.push(match self.kind {
            Kind::Line => Out::Feed(self.e),
            Kind::Arc { ccw, centre } => Out::Arc {
                ccw,
                centre,
                end: self.e,
            },
        });
    }

    /// Follow the segment up to its end if it climbs (towards +x); `Ok(true)` when it does
    /// not (for a counterclockwise arc: after following it to its top).
    fn climb(&self, at: &mut C, out: &mut Vec<Out>) -> Result<bool, String> {
        match self.kind {
            Kind::Line => {
                if self.e.im + TOL < self.s.im {
                    return Ok(true);
                }
                if (*at - self.s).abs() > TOL {
                    return Err("How did we get here?".into());
                }
                out.push(Out::Feed(self.e));
                *at = self.e;
                Ok(false)
            }
            Kind::Arc { ccw: false, centre } => {
                if at.re > centre.re {
                    return Ok(true);
                }
                if (*at - self.e).abs() > 1e-3 {
                    out.push(Out::Arc {
                        ccw: false,
                        centre,
                        end: self.e,
                    });
                }
                *at = self.e;
                Ok(false)
            }
            Kind::Arc { ccw: true, centre } => {
                if at.re < centre.re {
                    return Ok(true);
                }
                let ep = self.top(centre);
                if (*at - ep).abs() > 1e-3 {
                    out.push(Out::Arc {
                        ccw: true,
                        centre,
                        end: ep,
                    });
                }
                *at = ep;
                Ok(true)
            }
        }
    }

    /// A counterclockwise arc's end, or its top when it goes past it.
    fn top(&self, centre: C) -> C {
        if self.e.re < centre.re {
            c(centre.re, centre.im + (self.s - centre).abs())
        } else {
            self.e
        }
    }

    /// G7x.1: from the layer's end, onto the segment where it is at the tool's depth and
    /// along it if it climbs.
    fn climb_only(&self, at: &mut C, out: &mut Vec<Out>) {
        match self.kind {
            Kind::Line => {
                if self.e.im < self.s.im {
                    return;
                }
                let Some(&z) = self.at_depth(at.im).first() else {
                    return;
                };
                at.re = z;
                out.push(Out::Feed(*at));
                out.push(Out::Feed(self.e));
                *at = self.e;
            }
            Kind::Arc { ccw, centre } => {
                let is = self.at_depth(at.im);
                let (Some(&first), Some(&last)) = (is.first(), is.last()) else {
                    return;
                };
                if !ccw {
                    if last > centre.re {
                        return;
                    }
                    at.re = last;
                    out.push(Out::Feed(*at));
                    if (*at - self.e).abs() > 1e-3 {
                        out.push(Out::Arc {
                            ccw,
                            centre,
                            end: self.e,
                        });
                    }
                    *at = self.e;
                } else {
                    if first < centre.re {
                        return;
                    }
                    at.re = first;
                    out.push(Out::Feed(*at));
                    let ep = self.top(centre);
                    if (*at - ep).abs() > 1e-3 {
                        out.push(Out::Arc {
                            ccw,
                            centre,
                            end: ep,
                        });
                    }
                    *at = ep;
                }
            }
        }
    }

    /// Go down along the segment to depth `x` (or its end when it ends above); `Ok(true)`
    /// when it does not descend. `fast`: the lead-in, at rapid.
    fn dive(&self, at: &mut C, x: f64, out: &mut Vec<Out>, fast: bool) -> Result<bool, String> {
        match self.kind {
            Kind::Line => {
                if self.s.im <= self.e.im + TOL {
                    return Ok(true);
                }
                let to = if x < self.e.im {
                    self.e
                } else {
                    let Some(&z) = self.at_depth(x).first() else {
                        return Err("x too large in straight dive".into());
                    };
                    c(z, x)
                };
                out.push(if fast { Out::Rapid(to) } else { Out::Feed(to) });
                *at = to;
                Ok(false)
            }
            Kind::Arc { ccw, centre } => {
                if (*at - self.e).abs() < TOL || (*at - self.e).re <= TOL {
                    *at = self.e;
                    return Ok(false);
                }
                let mut is = self.at_depth(x);
                if is.is_empty() {
                    is = self.at_depth(x - TOL);
                }
                let arc_to = |end: C, out: &mut Vec<Out>| out.push(Out::Arc { ccw, centre, end });
                if ccw {
                    if at.re - TOL > centre.re {
                        return Ok(true);
                    }
                    match is.last() {
                        Some(&z) if z <= centre.re => {
                            let ep = c(z, x);
                            arc_to(ep, out);
                            *at = ep;
                        }
                        _ => {
                            arc_to(self.e, out);
                            *at = self.e;
                        }
                    }
                    Ok(false)
                } else {
                    if at.re <= centre.re {
                        return Ok(true);
                    }
                    match is.first() {
                        None => {
                            arc_to(self.e, out);
                            *at = self.e;
                        }
                        // Met on the far side only: the layer steps down instead.
                        Some(&z) if z < centre.re => {}
                        Some(&z) => {
                            let ep = c(z, x);
                            arc_to(ep, out);
                            *at = ep;
                        }
                    }
                    Ok(false)
                }
            }
        }
    }
}

/// `next` after `prev`: both moved to where they meet (rs274's `intersect_end`).
fn intersect(prev: &mut Seg, next: &mut Seg) -> Result<(), String> {
    match (prev.kind, next.kind) {
        (Kind::Line, Kind::Line) => {
            let rot = (next.s - next.e).conj() / (next.s - next.e).abs();
            let ps = (prev.s - next.e) * rot;
            let pe = (prev.e - next.e) * rot;
            if (ps - pe).im == 0.0 {
                return Err("Cannot intersect parallel lines".into());
            }
            let f = ps.im / (ps - pe).im;
            let is = (ps + (pe - ps) * f) / rot + next.e;
            next.s = is;
            prev.e = is;
        }
        (Kind::Arc { centre, .. }, Kind::Line) => {
            if (next.s - prev.e).abs() < TOL {
                return Ok(());
            }
            let rot = (next.s - next.e).conj() / (next.s - next.e).abs();
            let pe = (prev.e - next.e) * rot;
            let pc = (centre - next.e) * rot;
            let p = nearest_on(pc, pe, rot, next.e, next.s);
            next.s = p;
            prev.e = p;
        }
        (Kind::Line, Kind::Arc { centre, .. }) => {
            if (next.s - prev.e).abs() < TOL {
                return Ok(());
            }
            let rot = (prev.s - prev.e).conj() / (prev.s - prev.e).abs();
            let pe = (next.e - prev.e) * rot;
            let pc = (centre - prev.e) * rot;
            let p = nearest_on(pc, pe, rot, prev.e, next.s);
            next.s = p;
            prev.e = p;
        }
        (Kind::Arc { centre: pcen, .. }, Kind::Arc { centre: ncen, .. }) => {
            let a = (next.s - ncen).abs();
            let b = (prev.s - pcen).abs();
            let cc = (ncen - pcen).abs();
            let cos_b = (cc * cc + a * a - b * b) / 2.0 / a / cc;
            let cos2 = (cos_b * cos_b).min(1.0);
            let rot = c(cos_b, (1.0 - cos2).sqrt());
            let is = rot * (pcen - ncen) / cc * a + ncen;
            prev.e = is;
            next.s = is;
        }
    }
    Ok(())
}

/// Where a line (rotated onto the real axis by `rot` about `origin`) meets the circle about
/// `pc` through `pe` (both rotated): of the two points, the one nearer `near`.
fn nearest_on(pc: C, pe: C, rot: C, origin: C, near: C) -> C {
    let b = (pc - pe).norm() - pc.im * pc.im;
    let b = if b < 0.0 { 0.0 } else { b.sqrt() };
    let s1 = real_over(pc.re + b, rot) + origin;
    let s2 = real_over(pc.re - b, rot) + origin;
    if (near - s1).abs() < (near - s2).abs() {
        s1
    } else {
        s2
    }
}

/// Make the corner `me` between `prev` and `next` (rs274's `corner_finish`): returns the
/// fillet's centre.
fn corner(me: &mut Seg, prev: &mut Seg, next: &mut Seg) -> Result<C, String> {
    let offset_pair = |d: f64| -> Result<(Seg, Seg), String> {
        let (mut p, mut n) = (prev.clone(), next.clone());
        p.offset(d);
        n.offset(d);
        Ok((p, n))
    };
    let (mut p, mut n) = offset_pair(me.finish)?;
    if (p.e - n.s).re > 1e-2 {
        me.finish = -me.finish;
        (p, n) = offset_pair(me.finish)?;
    }
    if (p.e - n.s).re > 1e-2 {
        return Err(format!("Corner finish failed at {}", show(prev.e)));
    }
    intersect(&mut p, &mut n)?;
    let centre = (p.e + n.s) / 2.0;
    p.offset(-me.finish);
    n.offset(-me.finish);
    me.s = p.e;
    prev.e = p.e;
    me.e = n.s;
    next.s = n.s;
    Ok(centre)
}

/// A point as C++ streams a `std::complex<double>`: `(re,im)`, 6 significant digits.
fn show(p: C) -> String {
    format!("({},{})", g_format(p.re, 6), g_format(p.im, 6))
}

/// C's `%.{digits}g`: `digits` significant digits, trailing zeros dropped, an exponent
/// below 1e-4 or from 10^digits on.
pub(super) fn g_format(v: f64, digits: usize) -> String {
    if v == 0.0 || !v.is_finite() {
        return if v == 0.0 { "0".into() } else { format!("{v}") };
    }
    let p = digits.max(1);
    let sci = format!("{v:.*e}", p - 1);
    let (mant, exp) = sci.split_once('e').unwrap_or((&sci, "0"));
    let exp: i32 = exp.parse().unwrap_or(0);
    let trim = |s: &str| -> String {
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s.to_string()
        }
    };
    if exp < -4 || exp >= p as i32 {
        let sign = if exp < 0 { '-' } else { '+' };
        format!("{}e{sign}{:02}", trim(mant), exp.abs())
    } else {
        let decimals = (p as i32 - 1 - exp).max(0) as usize;
        trim(&format!("{v:.decimals$}"))
    }
}

/// The largest number of steps one cycle may take (offset steps, layers and contour
/// segments walked): rs274 has no bound and loops for ever on some contours.
const MAX_STEPS: usize = 2_000_000;

fn endless() -> String {
    format!("the cycle does not end after {MAX_STEPS} steps (rs274 2.9.0~pre1 loops for ever on this contour)")
}

/// A contour being cut: the lead-in and the subroutine's segments, and how it was turned
/// and mirrored into the normal frame (rs274's `flip_state`: 4 turned, 2 x mirrored, 1 z
/// mirrored).
#[derive(Clone, Debug)]
pub(super) struct Contour {
    segs: Vec<Seg>,
    flip: u8,
}

impl Contour {
    pub(super) fn new(segs: Vec<Seg>) -> Contour {
        Contour { segs, flip: 0 }
    }

    /// Turn by -90 deg (z + ix to x - iz).
    fn rotate(&mut self) {
        for s in &mut self.segs {
            s.map(|p| -(p.times_i()), false);
        }
        self.flip ^= 4;
    }

    /// Mirror so that the contour runs towards -z with x growing.
    fn swap(&mut self) {
        let (Some(first), Some(last)) = (self.segs.first(), self.segs.last()) else {
            return;
        };
        let d = first.e - last.e;
        if d.im > 0.0 {
            for s in &mut self.segs {
                s.map(C::conj, true);
            }
            self.flip ^= 2;
        }
        if d.re < 0.0 {
            for s in &mut self.segs {
                s.map(|p| -p.conj(), true);
            }
            self.flip ^= 1;
        }
    }

    /// A move in the normal frame back in the program's frame.
    fn unmap(&self, o: Out) -> Out {
        let f = |p: C| -> C {
            match self.flip {
                0 => p,
                1 => -p.conj(),
                2 => p.conj(),
                3 => -p,
                4 => p.times_i(),
                5 => p.times_i().conj(),
                6 => -p.times_i().conj(),
                _ => -p.times_i(),
            }
        };
        let mirror = matches!(self.flip, 1 | 2 | 5 | 6);
        match o {
            Out::Rapid(p) => Out::Rapid(f(p)),
            Out::Feed(p) => Out::Feed(f(p)),
            Out::Arc { ccw, centre, end } => Out::Arc {
                ccw: ccw != mirror,
                centre: f(centre),
                end: f(end),
            },
        }
    }

    fn check_monotonic(&mut self) -> Result<(), String> {
        if let Some(f) = self.segs.first_mut() {
            if (f.e - f.s).re > 0.0 {
                f.s.re = f.e.re;
            }
        }
        if self.segs.iter().all(Seg::monotonic) {
            Ok(())
        } else {
            Err("Not monotonic".into())
        }
    }

    /// Make the fillets and chamfers, then drop segments shorter than 1e-3.
    fn finish_corners(&mut self) -> Result<(), String> {
        let n = self.segs.len();
        for h in 1..n.saturating_sub(1) {
            let (before, rest) = self.segs.split_at_mut(h);
            let (me, after) = rest.split_first_mut().expect("h < n");
            let (prev, next) = (&mut before[h - 1], &mut after[0]);
            match me.corner {
                Corner::None => {}
                Corner::Fillet => {
                    let centre = corner(me, prev, next)?;
                    let ccw = (me.s - centre).im > 0.0 || (me.e - centre).im > 0.0;
                    me.kind = Kind::Arc { ccw, centre };
                    me.finish = 0.0;
                }
                Corner::Chamfer => {
                    corner(me, prev, next)?;
                }
            }
        }
        // (rs274 erases what is shorter: a NaN size stays.)
        self.segs.retain(|s| s.size() >= 1e-3 || s.size().is_nan());
        Ok(())
    }

    /// Offset the contour (the lead-in kept, its end moved to the offset start) by
    /// `distance` away from the side the lead-in comes from.
    fn add_distance(&mut self, mut distance: f64, steps: &mut usize) -> Result<(), String> {
        let (Some(first), Some(last)) = (self.segs.first(), self.segs.last()) else {
            return Err("an empty contour".into());
        };
        let v1 = first.e - first.s;
        let v2 = last.s - first.s;
        if (v1 / v2).im < 0.0 {
            distance = -distance;
        }
        let mut lead = self.segs.remove(0);
        let segs = &mut self.segs;
        let mut current = 0.0;
        // rs274 reads past its list here: vpcut stops.
        let past = || {
            "the offset contour falls apart (rs274 2.9.0~pre1 reads past its segment list here)"
                .to_string()
        };
        while current != distance {
            *steps += 1;
            if *steps > MAX_STEPS {
                return Err(endless());
            }
            let mut step = 1e9f64;
            for s in segs.iter() {
                let h = s.size() / 2.0;
                if h < step {
                    step = h;
                }
            }
            let left = (distance - current).abs();
            if left < step {
                step = left;
            }
            if distance < 0.0 {
                step = -step;
            }
            let mut i = 0;
            while i < segs.len() {
                segs[i].offset(step);
                if segs[i].size() < 1e-3 {
                    segs.remove(i);
                } else {
                    i += 1;
                }
            }
            // Gaps: an arc about the old corner.
            let mut i = 0;
            while i + 1 < segs.len() {
                let n = i + 1;
                if (segs[i].e - segs[n].s).re > 1e-2 {
                    let (mut a, mut b) = (segs[i].clone(), segs[n].clone());
                    a.offset(-step);
                    b.offset(-step);
                    let centre = (a.e + b.s) / 2.0;
                    let arc = Seg::arc(distance > 0.0, segs[i].e, centre, segs[n].s);
                    segs.insert(n, arc);
                    i += 1;
                }
                i += 1;
            }
            // Segments that turned back go; neighbours meet.
            let mut i = 0;
            loop {
                if segs.is_empty() || i == segs.len() - 1 {
                    break;
                }
                if i >= segs.len() {
                    return Err(past());
                }
                if !segs[i].monotonic() {
                    if i == 0 {
                        return Err(past());
                    }
                    if segs[i].size() < segs[i - 1].size() {
                        segs.remove(i);
                    } else {
                        segs.remove(i - 1);
                    }
                    i = 0;
                }
                if i + 1 >= segs.len() {
                    return Err(past());
                }
                if segs[i].size() < 1e-3 {
                    segs.remove(i);
                    i = 0;
                } else {
                    let (a, b) = segs.split_at_mut(i + 1);
                    intersect(&mut a[i], &mut b[0])?;
                }
                i += 1;
            }
            current += step;
        }
        for i in 0..segs.len().saturating_sub(1) {
            let mid = (segs[i].e + segs[i + 1].s) / 2.0;
            segs[i].e = mid;
            segs[i + 1].s = mid;
        }
        let Some(f) = segs.first() else {
            return Err(past());
        };
        lead.e = f.s;
        segs.insert(0, lead);
        Ok(())
    }

    /// G70 from `start`: `passes` finishing passes from `d` to `e` away from the contour.
    pub(super) fn g70(mut self, start: C, d: f64, e: f64, passes: f64) -> Result<Vec<Out>, String> {
        self.segs[0].s = start;
        let mut steps = 0;
        // Which way the contour is monotonic: judged without the lead-in.
        let mut probe = self.clone();
        probe.segs.remove(0);
        probe.swap();
        if !probe.segs.iter().all(Seg::monotonic) {
            probe.rotate();
            probe.swap();
        }
        probe.check_monotonic()?;
        if probe.flip & 4 != 0 {
            self.rotate();
        }
        self.swap();
        self.finish_corners()?;
        self.check_monotonic()?;
        let mut out = Vec::new();
        // rs274 counts passes in an int from the P word (truncated).
        let mut pass = passes as i64;
        while pass > 0 {
            let distance = (pass - 1) as f64 * (d - e) / passes + e;
            let mut path = self.clone();
            path.add_distance(distance, &mut steps)?;
            let mut moves = vec![Out::Rapid(path.segs[0].s), Out::Rapid(path.segs[0].e)];
            for s in &path.segs[1..] {
                s.draw(&mut moves);
            }
            out.extend(moves.into_iter().map(|m| self.unmap(m)));
            pass -= 1;
        }
        Ok(out)
    }

    /// G71 (`turned` false) or G72 (true), `kind` 0 (pockets), 1 (none), 2 (pockets only),
    /// from `start`: leave `d`, cut `depth` deep layers, retract `retract`.
    pub(super) fn g71(
        mut self,
        turned: bool,
        kind: u32,
        start: C,
        d: f64,
        depth: f64,
        retract: f64,
    ) -> Result<Vec<Out>, String> {
        self.segs[0].s = start;
        if turned {
            self.rotate();
        }
        self.swap();
        self.finish_corners()?;
        self.check_monotonic()?;
        let mut steps = 0;
        self.add_distance(d, &mut steps)?;
        let delta = depth.max(2.0 * TOL);
        let escape = c(retract, retract);
        let mut out = Vec::new();
        let from = self.segs[0].s;
        out.push(Out::Rapid(from));
        let last = self.segs[self.segs.len() - 1].e;
        if last.im < from.im {
            self.segs.push(Seg::line(last, c(last.re, from.im)));
        }
        let mut pockets = vec![from];
        self.pocket(
            kind,
            from,
            0,
            &mut pockets,
            delta,
            escape,
            &mut out,
            &mut steps,
        )?;
        Ok(out.into_iter().map(|m| self.unmap(m)).collect())
    }

    /// Cut layers from `at` on segment `p` (rs274's `pocket`, its tail calls as a loop).
    #[allow(clippy::too_many_arguments)]
    fn pocket(
        &self,
        mut kind: u32,
        mut at: C,
        mut p: usize,
        starts: &mut Vec<C>,
        delta: f64,
        escape: C,
        out: &mut Vec<Out>,
        steps: &mut usize,
    ) -> Result<(), String> {
        let segs = &self.segs;
        'pocket: loop {
            let mut x = starts.last().expect("one start").im;
            if kind == 2 {
                // The first layer is skipped: down the contour to its first climb.
                while p < segs.len() {
                    if segs[p].dive(&mut at, -1e9, out, p == 0)? {
                        break;
                    }
                    p += 1;
                }
                kind = 3;
            }
            while p < segs.len() {
                *steps += 1;
                if *steps > MAX_STEPS {
                    return Err(endless());
                }
                while x - TOL > at.im {
                    x -= delta;
                }
                if segs[p].dive(&mut at, x, out, p == 0)? {
                    if kind == 1 {
                        while p < segs.len() {
                            segs[p].climb_only(&mut at, out);
                            p += 1;
                        }
                    } else {
                        while p < segs.len() {
                            if segs[p].climb(&mut at, out)? {
                                if kind == 3 {
                                    let top = starts.last().expect("one start").im;
                                    if at.im > top && starts.len() > 1 {
                                        starts.pop();
                                    }
                                    if starts.len() == 1 {
                                        starts.push(at);
                                    }
                                }
                                continue 'pocket;
                            }
                            p += 1;
                        }
                    }
                    return Ok(());
                }
                if (at.im - x).abs() > TOL {
                    // Below this segment's reach: on to the next.
                    p += 1;
                    continue;
                }
                for (ip, seg) in segs.iter().enumerate().skip(p) {
                    let is = seg.at_depth(at.im);
                    let (Some(&first), Some(&last)) = (is.first(), is.last()) else {
                        continue;
                    };
                    let dest_z = if ip != p { first } else { last };
                    let dist = (dest_z - at.re).abs();
                    if dest_z - TOL > at.re {
                        continue;
                    }
                    if dist < TOL {
                        if p == ip {
                            continue;
                        } else if (at - seg.s).abs() < TOL {
                            p = ip;
                            break;
                        } else {
                            x -= delta;
                            break;
                        }
                    }
                    let mut dest = at;
                    dest.re = dest_z;
                    out.push(Out::Feed(dest));
                    let scale = (dist / 2.0 / escape.re).min(1.0);
                    let esc = escape * scale;
                    out.push(Out::Rapid(dest + esc));
                    out.push(Out::Rapid(at - esc.conj()));
                    out.push(if p == 0 {
                        Out::Rapid(at)
                    } else {
                        Out::Feed(at)
                    });
                    x -= delta;
                    break;
                }
            }
            return Ok(());
        }
    }
}

//! The model meshed while the columns stream ([`simulate_meshed`]): the pipeline's
//! streamed run (`pipeline::simulate_with`) hands the stock mesh's builder the raw columns
//! of one interval at a time, from a kept column to the next (`mesh::kept_columns`: they
//! depend only on the grid, the blank and the thread), and the interval gives its
//! profiles: the kept column's and those the refinement adds between the two (it reads
//! the raw columns in between, so they are held with the interval). The mesh is then
//! assembled from the profiles in column order, exactly as `mesh::build_scene` assembles
//! the full grid's, from the same per-column functions: the `.glb` is byte for byte the
//! one the full-grid run gives (tested on every scene), while the run holds a buffer of
//! the widest interval per thread instead of the whole grid. The model's focus (the worst
//! dexel's radius) comes from its column, cut once more after the run.

use crate::analysis::compare::Deviation;
use crate::job::Job;
use crate::model::stock::Surface;
use crate::model::thread::ThreadSpec;
use crate::output::mesh::{
    assemble, finish_scene, focus, kept_columns, legend, mesh_tolerance, surface, worst,
    SceneOptions,
};
use crate::output::profile::{refined, surfacers, Dexels, MeshColumn, Profile, Shape};
use crate::output::scene::Scene;
use crate::pipeline::{plan_grid, simulate_with, Held, SimError, SimOptions, Sink};
use crate::report::Report;

/// A run whose stock was meshed while its columns streamed ([`simulate_meshed`]).
#[derive(Debug)]
pub struct Meshed {
    /// The report, byte for byte [`crate::simulate`]'s.
    pub report: Report,
    /// The deviation from the ideal thread, exact.
    pub deviation: Deviation,
    scene: Scene,
}

impl Meshed {
    /// The scene, byte for byte what [`crate::build_scene`] gives on the full grid, its
    /// summary from `report` as it is now (the caller may have completed it, as it does
    /// an [`crate::Outcome`]'s before building a scene).
    pub fn into_scene(self) -> Scene {
        Scene {
            summary: self.report.summary_json(self.scene.legend.scale_mm),
            ..self.scene
        }
    }
}

/// Simulate a job as [`crate::simulate`] does and build its scene as
/// [`crate::build_scene`] does, without keeping the whole grid: the columns stream as in
/// [`crate::simulate_report`], and the mesh is built from each interval between two kept
/// columns while its raw columns are held (a buffer of the widest interval per thread,
/// which the dexel budget counts, and the mesh's profiles).
pub fn simulate_meshed(
    job: &Job,
    sim: &SimOptions,
    opts: &SceneOptions,
) -> Result<Meshed, SimError> {
    let tol = job.sim.tolerance;
    let (grid, _) = plan_grid(job)?;
    let shape = Shape {
        grid,
        outer: job.blank.diameter / 2.0,
        inner: job.blank.bore / 2.0,
    };
    let cut = surface(&job.thread);
    if !shape.surfaces().contains(&cut) {
        // Not a job a file gives (an internal thread needs a bore): the full grid.
        let out = crate::pipeline::simulate(job, sim)?;
        let scene = crate::output::mesh::build_scene(job, &out, opts);
        return Ok(Meshed {
            report: out.report,
            deviation: out.deviation,
            scene,
        });
    }
    let e = mesh_tolerance(job, opts);
    let sink = MeshSink {
        shape,
        thread: &job.thread,
        cut,
        tol,
        e,
        bounds: kept_columns(&shape, &job.thread, 0.5 * e),
        blank: vec![0.0; grid.n_z],
    };
    let run = simulate_with(job, sim, &sink)?;
    let columns: Vec<MeshColumn> = run.parts.into_iter().flatten().collect();
    let stock = assemble(&shape, &job.thread, columns);
    let legend = legend(&run.deviation, tol);
    let q0 = match cut {
        Surface::Outer => shape.outer,
        Surface::Inner => -shape.inner,
    };
    let focus = focus(&run.deviation, &grid, tol, |i, j| {
        let (k, col) = run.probe.as_ref()?;
        (*k == i).then(|| cut.sense() * (col[j] as f64 + q0))
    });
    let scene = finish_scene(job, &shape, opts, legend, stock, focus, &run.report);
    Ok(Meshed {
        report: run.report,
        deviation: run.deviation,
        scene,
    })
}

/// The mesh's builder as a pipeline [`Sink`].
struct MeshSink<'a> {
    shape: Shape,
    thread: &'a ThreadSpec,
    /// The surface the thread is cut on (the other one of a tube stays the blank).
    cut: Surface,
    tol: f64,
    e: f64,
    /// The kept columns.
    bounds: Vec<usize>,
    /// An uncut column: the other surface of a tube.
    blank: Vec<f32>,
}

/// An interval's held columns as [`Dexels`], the uncut surface as the blank.
struct HeldDexels<'a, 'b> {
    held: &'b Held<'a>,
    cut: Surface,
    blank: &'b [f32],
}

impl Dexels for HeldDexels<'_, '_> {
    fn column(&self, s: Surface, u: usize) -> &[f32] {
        if s == self.cut {
            self.held.column(u)
        } else {
            self.blank
        }
    }

    fn edge(&self, s: Surface, u: usize) -> Option<&[f32]> {
        if s == self.cut {
            self.held.edge(u)
        } else {
            None
        }
    }
}

impl Sink for MeshSink<'_> {
    type Part = Vec<MeshColumn>;
    /// The profiles of the interval's last column (the next interval's first).
    type Carry = Option<MeshColumn>;

    fn bounds(&self) -> &[usize] {
        &self.bounds
    }

    fn interval(&self, _: usize, held: &Held<'_>, carry: &mut Self::Carry) -> Vec<MeshColumn> {
        let dexels = HeldDexels {
            held,
            cut: self.cut,
            blank: &self.blank,
        };
        let sfs = surfacers(&self.shape, &dexels, self.thread, self.tol, self.e);
        let (ua, ub) = (held.first, held.last());
        let pa: Vec<Profile> = match carry.take() {
            Some((u, p)) if u == ua => p,
            _ => sfs.iter().map(|sf| sf.profile(ua)).collect(),
        };
        let pb: Vec<Profile> = sfs.iter().map(|sf| sf.profile(ub)).collect();
        let added = refined(&sfs, ua, &pa, ub, &pb);
        *carry = Some((ub, pb));
        let mut out = Vec::with_capacity(1 + added.len());
        out.push((ua, pa));
        out.extend(added);
        out
    }

    fn probe(&self, dev: &Deviation) -> Option<usize> {
        worst(dev, &self.shape.grid, self.tol).map(|w| w.2)
    }
}

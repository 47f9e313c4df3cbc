//! `vpcut plan`: every planned screw in `tests/data/plans/` (equal groove, equal tooth,
//! Tr100x12, three starts, a decreasing pitch, an internal thread) simulates clean; written
//! in every dialect and read back by vpcut's own interpreter (strictly: every word
//! understood) it gives exactly the planned passes; LinuxCNC's chained G33 approximation
//! simulates clean too.

use crate::support::root;
use vpcut::post::{self, Post};
use vpcut::{simulate, Job, SimOptions, Verdict};

/// Each post and the dialect its program is read back in: the 802D's program also under the
/// 840D (`--dialect siemens-840d` writes it, and the 840D runs it unchanged).
const POSTS: [(Post, &str); 6] = [
    (Post::Fanuc, "fanuc"),
    (Post::FanucMacro, "fanuc"),
    (Post::Gsk980, "gsk980"),
    (Post::Siemens802d, "siemens-802d"),
    (Post::Siemens802d, "siemens-840d"),
    (Post::Linuxcnc, "linuxcnc"),
];

fn plans() -> Vec<(String, Job)> {
    let dir = root().join("tests/data/plans");
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    files.sort();
    files
        .into_iter()
        .map(|p| {
            let name = p.file_name().unwrap().to_string_lossy().into_owned();
            let text = std::fs::read_to_string(&p).unwrap();
            let job = Job::from_toml(&text, &name).unwrap_or_else(|e| panic!("{name}: {e}"));
            (name, job)
        })
        .collect()
}

/// Clean: the verdict passes and nothing is reported, not even a warning.
fn assert_clean(what: &str, job: &Job) {
    let out = simulate(job, &SimOptions::default()).unwrap();
    let r = &out.report;
    assert_eq!(r.verdict, Verdict::Pass, "{what}:\n{}", r.summary());
    assert!(r.findings.is_empty(), "{what}:\n{}", r.summary());
}

#[test]
fn planned_screws_round_trip_in_every_dialect_and_simulate_clean() {
    let plans = plans();
    assert_eq!(plans.len(), 6);
    assert_eq!(
        Post::from_name("siemens-840d", false),
        Some(Post::Siemens802d)
    );
    assert_eq!(Post::from_name("siemens-840d", true), None);
    for (name, job) in &plans {
        let plan = job.plan.as_ref().expect("kind = plan");
        assert_eq!(job.passes, plan.passes());
        assert!(plan.check.max_leftover <= plan.tolerance, "{name}");
        assert!(plan.check.max_gouge <= plan.tolerance, "{name}");
        assert_clean(name, job);
        let tool_id = job.tools[plan.tool].id;
        for (p, dialect) in POSTS {
            let what = format!("{name} {p:?}");
            let text = post::post(plan, tool_id, &job.name, p).unwrap();
            let back = job
                .with_program("plan.nc", &text, dialect)
                .unwrap_or_else(|e| panic!("{what}: {e}\n{text}"));
            assert!(back.program_warnings.is_empty(), "{what}");
            let want = post::toolpath(plan, p);
            assert_eq!(post::differ(&want, &back.passes), None, "{what}");
            if p == Post::Linuxcnc && plan.lead_change != 0.0 {
                // A chain, not the plan's passes: simulated on its own.
                assert!(back.passes.len() > job.passes.len(), "{what}");
                assert_clean(&what, &back);
            } else {
                assert_eq!(back.passes, job.passes, "{what}");
            }
        }
    }
}

/// Seed 002's screw: the plan takes no more passes than seed 002's method (R11 + 1 per
/// layer, 5 x 3 = 15), and, unlike it, covers the groove: its widest groove (16 - 3 = 13
/// mm) less the 3 mm tool is spread over M = ceil(10 / 2.998) = 4 steps of 2.5 mm.
#[test]
fn seed002_count_against_seed002_method() {
    let plans = plans();
    let job = &plans
        .iter()
        .find(|(n, _)| n == "seed002-equal-tooth.toml")
        .unwrap()
        .1;
    let plan = job.plan.as_ref().unwrap();
    assert_eq!(plan.seed002_passes, Some(15));
    assert_eq!(plan.passes().len(), 15);
    assert!(plan.layers.iter().all(|l| l.count == 5));
    // At the last turn the five passes are (13 - 3)/4 = 2.5 mm apart: step plus the far
    // family's spread over the turns reaches that by the widest groove.
    let l = &plan.layers[0];
    assert!((l.lead_step - 1.5 / 4.0).abs() < 1e-12);
}

/// The line check can fail: leave out the middle position of every layer of the equal
/// groove plan and a ridge stands above the tolerance.
#[test]
fn the_line_check_sees_a_missing_pass() {
    let plans = plans();
    let job = &plans
        .iter()
        .find(|(n, _)| n == "seed004-tr100x12.toml")
        .unwrap()
        .1;
    let plan = job.plan.as_ref().unwrap();
    let mut thin = plan.clone();
    for l in &mut thin.layers {
        if l.count >= 3 {
            // Two positions at the walls: the middle one is missing.
            l.step *= f64::from(l.count - 1);
            l.count = 2;
        }
    }
    let check = vpcut::plan::line_check(&thin.passes(), &job.thread, &job.tools[plan.tool]);
    assert!(check.max_leftover > 0.1, "{check:?}");
}

/// With a tolerance class the planner aims at the middle of the zone: `M30x2-6H` (D2
/// 28.701 .. 28.925, ISO 965-2) and `M30x2-6g` (d2 28.493 .. 28.663), planned, posted as a
/// FANUC program, read back and simulated, pass the gauges with the functional and simple
/// pitch diameters at the zone's middle (28.813, 28.578) within 1 um.
#[test]
fn a_classed_thread_is_planned_to_the_middle_of_its_zone() {
    let text = std::fs::read_to_string(
        crate::support::root().join("tests/data/plans/internal-m30x2.toml"),
    )
    .unwrap();
    let internal = text
        .replace("side = \"internal\"\n", "")
        .replace("form = \"iso-metric\"", "designation = \"M30x2-6H\"")
        .replace("major_diameter = 30.0\n", "")
        .replace("pitch = 2.0\n", "")
        .replace("minor_diameter = 27.835\n", "")
        .replace("bore = 27.835", "bore = 28.0");
    let external = internal
        .replace("M30x2-6H", "M30x2-6g")
        .replace("bore = 28.0\n", "")
        .replace("diameter = 40.0", "diameter = 29.8")
        .replace("z_start = -2.0\n", "z_start = -2.0\nside = \"external\"\n")
        // The external root flat of the d3 profile, P/6.
        .replace("tip_flat = 0.25", "tip_flat = 0.3333333333333333");
    for (t, mid) in [(internal, 28.813), (external, 28.578)] {
        let job = Job::from_toml(&t, "plan.toml").unwrap_or_else(|e| panic!("{e}"));
        let plan = job.plan.as_ref().expect("kind = plan");
        let program = post::post(plan, job.tools[plan.tool].id, &job.name, Post::Fanuc).unwrap();
        let back = job.with_program("plan.nc", &program, "fanuc").unwrap();
        let r = vpcut::simulate_report(&back, &vpcut::SimOptions::default()).unwrap();
        let g = r.gauge.as_ref().expect("a gauge section");
        assert_eq!(g.verdict, "pass", "{g:?}");
        let f = g.functional_diameter_mm.unwrap();
        let s = g.pitch_diameter_mm.unwrap();
        assert!(
            (f - mid).abs() < 1e-3 && (s.min - mid).abs() < 1e-3,
            "{f} {s:?} vs {mid}"
        );
    }
}

//! Okuma OSP-P programs through jobs (issue 27): a whole part program (face, turn, the G71
//! compound thread cutting cycle) is cut and gauged, against the closed form of the
//! clean cut.

use vpcut::{simulate_report, Job, SimOptions};

/// `tests/data/okuma/m30x2.toml`: M30x2-6g turned to the major 29.8 and threaded by G71
/// (pattern 3, single edge) to the root X27.423. A clean cut by a 60 deg insert with a P/6
/// flat at root diameter X has the functional and simple pitch diameters
/// `X + (P/2 - P/6) cot 30 = X + 1.154701` (P = 2), inside 6g's 28.493..28.663 (ISO 965-2),
/// and the turned major 29.8 inside 29.682..29.962: the gauges pass with no finding. The
/// same program with the root at 27.3 (0.123 deeper) cuts the pitch diameter 28.454701,
/// under the NOT GO limit 28.493: the gauge fails.
#[test]
fn the_okuma_m30x2_program_cuts_the_closed_form_thread() {
    let dir = crate::support::root().join("tests/data/okuma");
    let text = std::fs::read_to_string(dir.join("m30x2.toml")).unwrap();
    let run = |root: &str| {
        let load = |f: &str| {
            let t = std::fs::read_to_string(dir.join(f)).ok()?;
            Some(t.replace("X27.423", root))
        };
        let job = Job::from_toml_with(&text, "m30x2.toml", &load).unwrap_or_else(|e| panic!("{e}"));
        simulate_report(&job, &SimOptions::default()).unwrap()
    };
    let mid = run("X27.423");
    let g = mid.gauge.as_ref().unwrap();
    assert_eq!(g.verdict, "pass", "{g:?}");
    assert_eq!(mid.verdict, vpcut::Verdict::Pass, "{:?}", mid.findings);
    let fd = g.functional_diameter_mm.unwrap();
    assert!(
        (fd - (27.423 + 1.154701)).abs() <= g.resolution_mm.max(1e-4),
        "{fd}"
    );
    let major = g.major_diameter_mm.unwrap().max;
    assert!((major - 29.8).abs() <= g.resolution_mm.max(1e-4), "{major}");
    let deep = run("X27.3");
    let g = deep.gauge.as_ref().unwrap();
    assert_eq!(g.verdict, "fail", "{g:?}");
    let pd = g.pitch_diameter_mm.unwrap().min;
    assert!(
        (pd - (27.3 + 1.154701)).abs() <= g.resolution_mm.max(1e-4),
        "{pd}"
    );
}

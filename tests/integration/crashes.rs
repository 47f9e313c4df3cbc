//! Issue 28: programs that would scrap the part or break the insert on the machine, each
//! against its corrected twin (`tests/data/crash/<case>/`: `job.toml`, `crash.nc` as
//! written, `fixed.nc` corrected; the README there derives every expected number by hand).
//! The crash fails with its finding at the offending block; the fixed program passes.

use crate::support::root;
use vpcut::{simulate, Finding, FindingKind, Job, Report, SimOptions};

/// The case's job run with `program` (`crash.nc` or `fixed.nc`) as its program.
pub(crate) fn case_report(case: &str, program: &str) -> Report {
    let dir = root().join("tests/data/crash").join(case);
    let text = std::fs::read_to_string(dir.join("job.toml")).unwrap();
    let load = |f: &str| {
        let f = if f == "crash.nc" { program } else { f };
        std::fs::read_to_string(dir.join(f)).ok()
    };
    let job = Job::from_toml_with(&text, "job.toml", &load).unwrap_or_else(|e| panic!("{e}"));
    simulate(&job, &SimOptions::default())
        .unwrap_or_else(|e| panic!("{e}"))
        .report
}

fn of_kind(r: &Report, kind: FindingKind) -> Vec<&Finding> {
    r.findings.iter().filter(|f| f.kind == kind).collect()
}

#[test]
fn a_g76_started_under_the_crest_rapids_through_it_at_its_block() {
    let r = case_report("rapid-below-crest", "crash.nc");
    assert_eq!(r.verdict, vpcut::Verdict::Fail);
    let hits = of_kind(&r, FindingKind::RapidCut);
    // One finding for the G76 block (N60, line 9): its passes' rapids back along the bar
    // at X28 run (30 - 28) / 2 = 1 mm under the bar's crest.
    assert_eq!(hits.len(), 1, "{:#?}", r.findings);
    let h = hits[0];
    assert_eq!((h.file.as_deref(), h.line), (Some("crash.nc"), Some(9)));
    assert!((h.value.unwrap() - 1.0).abs() < 1e-6, "{h:?}");
    assert!(h.message.contains("T3"), "{}", h.message);
    let z = h.z_mm.unwrap();
    assert!((-39.5 - 0.1667..=0.0).contains(&z), "{z}");

    let ok = case_report("rapid-below-crest", "fixed.nc");
    assert!(of_kind(&ok, FindingKind::RapidCut).is_empty());
    assert_eq!(ok.verdict, vpcut::Verdict::Pass, "{:#?}", ok.findings);
}

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
    assert!(h.message.contains("T0303"), "{}", h.message);
    let z = h.z_mm.unwrap();
    assert!((-39.5 - 0.1667..=0.0).contains(&z), "{z}");

    let ok = case_report("rapid-below-crest", "fixed.nc");
    assert!(of_kind(&ok, FindingKind::RapidCut).is_empty());
    assert_eq!(ok.verdict, vpcut::Verdict::Pass, "{:#?}", ok.findings);
}

/// A small M30x2 job on a 30 mm bar whose `[machine]` says 200 rpm, with `program` (FANUC)
/// as `crash.nc` and `machine` added to its `[machine]` table.
fn small_job(program: &str, machine: &str) -> Result<Job, vpcut::JobError> {
    let text = format!(
        r#"
[blank]
diameter = 30.0
length = 60.0
[thread]
form = "iso-metric"
major_diameter = 30.0
pitch = 2.0
length = 36.0
z_start = -1.0
[[tool]]
id = 3
kind = "threading"
angle = 60.0
tip_flat = 0.3333333333
reference = "tip"
[program]
file = "crash.nc"
dialect = "fanuc"
decimal_point = "calculator"
[machine]
spindle_rpm = 200
max_feed = 5000
{machine}
[simulation]
axial_spacing = 0.05
angular_cells = 72
measure_generators = 2
"#
    );
    let prog = program.to_string();
    Job::from_toml_with(&text, "job.toml", &move |f: &str| {
        (f == "crash.nc").then(|| prog.clone())
    })
}

#[test]
fn the_feed_check_uses_the_programs_spindle_speed() {
    // G92 F4.0 at G97 S1500: 6000 mm/min over the 5000 limit, although [machine] says 200
    // rpm (800 mm/min); at S1000 it is 4000. Without any S the machine's 200 rpm stands.
    let prog = |s: &str| format!("T0303\n{s}\nG0 X32 Z5\nG92 X28 Z-30 F4.0\nG0 X100 Z100\nM30\n");
    let feed = |s: &str| {
        let job = small_job(&prog(s), "").unwrap_or_else(|e| panic!("{e}"));
        let r = vpcut::simulate_report(&job, &SimOptions::default()).unwrap();
        r.findings
            .into_iter()
            .filter(|f| f.kind == FindingKind::FeedLimit)
            .map(|f| f.value.unwrap())
            .collect::<Vec<_>>()
    };
    assert_eq!(feed("G97 S1500 M03"), [6000.0]);
    assert!(feed("G97 S1000 M03").is_empty());
    assert!(feed("M03").is_empty());
    assert_eq!(small_job(&prog("M03"), "").unwrap().pass_rpm, [200.0]);
    // G96 S200 under G50 S3000 threads X28 at min(3000, 1000 x 200 / (pi x 28)) = 2273.6
    // rpm: 9094.6 mm/min at lead 4.
    let job = small_job(&prog("G50 S3000\nG96 S200 M03"), "").unwrap();
    let want = 1000.0 * 200.0 / (std::f64::consts::PI * 28.0);
    assert!((job.pass_rpm[0] - want).abs() < 1e-9, "{:?}", job.pass_rpm);
    let job = small_job(&prog("G50 S1200\nG96 S200 M03"), "").unwrap();
    assert_eq!(job.pass_rpm, [1200.0]);
}

#[test]
fn tool_offsets_come_from_the_job_and_a_missing_one_is_a_warning_at_its_block() {
    // [machine] offsets.3: geometry x -0.02 and wear x -0.08 move T0303's point 0.1 down in
    // diameter and wear z 0.05 along z: G92 X28 cuts at X27.9, from Z5.05 to Z-29.95.
    let prog = "T0303\nG97 S500 M03\nG0 X32 Z5\nG92 X28 Z-30 F2.0\nG0 X100 Z100\nM30\n";
    let job = small_job(
        prog,
        "offsets.3 = { x = -0.02, wear_x = -0.08, wear_z = 0.05 }",
    )
    .unwrap_or_else(|e| panic!("{e}"));
    let p = &job.passes[0];
    assert!((p.x_start - 27.9).abs() < 1e-12 && (p.z_start - 5.05).abs() < 1e-12);
    assert!((p.z_end + 29.95).abs() < 1e-12);
    assert!(job.program_warnings.is_empty());
    // T0304 with only offset 3 in the job: a warning at line 1, the pass as programmed.
    let job = small_job(&prog.replace("T0303", "T0304"), "offsets.3 = { x = -0.1 }").unwrap();
    assert_eq!(job.passes[0].x_start, 28.0);
    let w = &job.program_warnings;
    assert_eq!(w.len(), 1, "{w:?}");
    assert_eq!(w[0].line, 1);
    assert!(w[0].message.contains("tool offset 4"), "{}", w[0].message);
    // An offset number out of 1..99 is an error at its key.
    let e = small_job(prog, "offsets.100 = { x = 0.0 }").unwrap_err();
    assert!(e.to_string().contains("machine.offsets.100"), "{e}");
}

/// The radial depths (mm) of the M30x2 cases' G76 `P010060 Q100 R0.05` / `P1227 Q400`, by
/// hand: 0.4 sqrt(n) while over the 0.1 minimum cut (0.4, 0.566, 0.693, 0.8), then the
/// minimum cut (0.9, 1.0, 1.1; 1.2 would pass k - d = 1.177), k - d, then k once.
pub(crate) const G76_DEPTHS: [f64; 9] = [
    0.4,
    0.565_685_424_949_238,
    0.692_820_323_027_550_9,
    0.8,
    0.9,
    1.0,
    1.1,
    1.177,
    1.227,
];

/// The case's job with `program` and `edits` to its TOML (`support::with`).
pub(crate) fn case_job(case: &str, program: &str, edits: &[(&str, &str, &str)]) -> Job {
    case_job_text(case, program, &|t| crate::support::with(t, edits))
}

/// The case's job with `program`, its TOML text changed by `edit`.
fn case_job_text(case: &str, program: &str, edit: &dyn Fn(&str) -> String) -> Job {
    let dir = root().join("tests/data/crash").join(case);
    let text = edit(&std::fs::read_to_string(dir.join("job.toml")).unwrap());
    let load = |f: &str| {
        let f = if f == "crash.nc" { program } else { f };
        std::fs::read_to_string(dir.join(f)).ok()
    };
    Job::from_toml_with(&text, "job.toml", &load).unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn a_g76_without_its_first_block_says_which_parameters_it_cut_with() {
    // k = 1.227, dd = 0.4. Without the first block (vpcut's defaults, no minimum cut, no
    // allowance): 0.4 sqrt(n) < 1.227 for n = 1..9 (0.4 x 3 = 1.2), then k, then m = 1
    // finishing pass at k: 11 passes. With P010060 Q100 R0.05: 0.4, 0.566, 0.693, 0.8, then
    // the minimum cut: 0.9, 1.0, 1.1 (1.2 would pass k - d = 1.177), 1.177, k: 9.
    let job = case_job("g76-first-block-missing", "crash.nc", &[]);
    assert_eq!(job.passes.len(), 11);
    let w = &job.program_warnings;
    assert_eq!(w.len(), 1, "{w:?}");
    assert_eq!((w[0].file.as_str(), w[0].line), ("crash.nc", 8));
    for said in [
        "without its first block",
        "1 finishing pass",
        "tool angle 60 deg",
        "minimum cut 0 mm",
        "finishing allowance 0 mm",
    ] {
        assert!(w[0].message.contains(said), "{said}: {}", w[0].message);
    }
    assert!(w[0].hint.as_deref().unwrap().contains("5140"));
    let r = case_report("g76-first-block-missing", "crash.nc");
    let found = of_kind(&r, FindingKind::Program);
    assert_eq!((found.len(), found[0].line), (1, Some(8)));

    let fixed = case_job("g76-first-block-missing", "fixed.nc", &[]);
    assert_eq!(fixed.passes.len(), 9);
    assert!(fixed.program_warnings.is_empty());
    let x: Vec<f64> = fixed.passes.iter().map(|p| p.x_start).collect();
    assert!((G76_DEPTHS[1] - 0.4 * 2f64.sqrt()).abs() < 1e-15);
    assert!((G76_DEPTHS[2] - 0.4 * 3f64.sqrt()).abs() < 1e-15);
    for (x, d) in x.iter().zip(G76_DEPTHS) {
        assert!((x - (27.546 + 2.0 * (1.227 - d))).abs() < 1e-9, "{x} {d}");
    }

    // The machine's parameters in the job: the same nine passes, and the warning says them.
    let job = case_job(
        "g76-first-block-missing",
        "crash.nc",
        &[
            ("machine", "g76_min_cut", "0.1"),
            ("machine", "g76_finish_allowance", "0.05"),
        ],
    );
    assert_eq!(job.passes, fixed.passes);
    let m = &job.program_warnings[0].message;
    assert!(
        m.contains("minimum cut 0.1 mm") && m.contains("finishing allowance 0.05 mm"),
        "{m}"
    );
}

#[test]
fn the_g76_parameters_are_checked_key_by_key() {
    let dir = root().join("tests/data/crash/g76-first-block-missing");
    let text = std::fs::read_to_string(dir.join("job.toml")).unwrap();
    let load = |f: &str| std::fs::read_to_string(dir.join(f)).ok();
    for (key, value, says) in [
        ("g76_tool_angle", "45", "80, 60, 55, 30, 29, 0"),
        ("g76_finish_passes", "0", "1 to 99"),
        ("g76_min_cut", "-0.1", "machine.g76_min_cut"),
        ("g76_finish_allowance", "20", "at most 10 mm"),
    ] {
        let t = crate::support::with(&text, &[("machine", key, value)]);
        let e = Job::from_toml_with(&t, "job.toml", &load).unwrap_err();
        assert!(e.to_string().contains(says), "{key}: {e}");
        assert!(e.to_string().contains(key), "{key}: {e}");
    }
}

#[test]
fn a_first_cut_the_insert_cannot_stand_is_an_error_at_its_block() {
    // G76 Q1200 with k = 1.227 and d = 0.05: 1.2 sqrt(1) already passes k - d = 1.177, so
    // the first pass cuts 1.177 under the bar's crest, over the insert's 0.4; then k (0.05,
    // over the 0.03 minimum).
    let r = case_report("first-cut-too-deep", "crash.nc");
    assert_eq!(r.verdict, vpcut::Verdict::Fail);
    let d = of_kind(&r, FindingKind::DepthPerPass);
    assert_eq!(d.len(), 1, "{:#?}", r.findings);
    assert_eq!(
        (d[0].file.as_deref(), d[0].line),
        (Some("crash.nc"), Some(9))
    );
    assert_eq!(d[0].pass, Some(1));
    assert!((d[0].value.unwrap() - 1.177).abs() < 1e-6, "{:?}", d[0]);
    assert!(d[0].is_error());
    // Q400: 0.4, then the increments 0.166, 0.127, 0.107, 0.1 (minimum cut) three times,
    // 0.077, 0.05: all within [0.03, 0.4].
    let ok = case_report("first-cut-too-deep", "fixed.nc");
    assert!(of_kind(&ok, FindingKind::DepthPerPass).is_empty());
    assert_eq!(ok.verdict, vpcut::Verdict::Pass, "{:#?}", ok.findings);
    // A minimum of 0.06 makes the last pass (0.05) a warning at the block, not an error.
    let job = case_job_text("first-cut-too-deep", "fixed.nc", &|t| {
        t.replace("min_depth_per_pass = 0.03", "min_depth_per_pass = 0.06")
    });
    let r = vpcut::simulate_report(&job, &SimOptions::default()).unwrap();
    let d = of_kind(&r, FindingKind::DepthPerPass);
    assert_eq!(d.len(), 1, "{:#?}", r.findings);
    assert!(!d[0].is_error() && d[0].pass == Some(9) && d[0].line == Some(9));
    assert!((d[0].value.unwrap() - 0.05).abs() < 1e-6);
}

#[test]
fn a_g76_infeed_beyond_the_inserts_flank_is_a_warning_at_its_block() {
    // G76 P010060 flank-infeeds at 30 deg; a 55 deg insert's trailing flank stands at 27.5:
    // fed into the wall. With the 60 deg insert the edge slides along it: no finding.
    let job = case_job_text("rapid-below-crest", "fixed.nc", &|t| {
        t.replace("angle = 60.0", "angle = 55.0")
    });
    let r = vpcut::simulate_report(&job, &SimOptions::default()).unwrap();
    let w = of_kind(&r, FindingKind::InfeedAngle);
    assert_eq!(w.len(), 1, "{:#?}", r.findings);
    assert_eq!((w[0].line, w[0].pass), (Some(9), Some(2)));
    assert!((w[0].value.unwrap() - 30.0).abs() < 1e-6 && !w[0].is_error());
    assert!(
        w[0].message.contains("trailing flank's 27.50 deg"),
        "{}",
        w[0].message
    );
    let ok = case_report("rapid-below-crest", "fixed.nc");
    assert!(of_kind(&ok, FindingKind::InfeedAngle).is_empty());
}

#[test]
fn a_thread_run_into_the_shoulder_is_a_gouge_of_the_part_at_its_block() {
    // The G76 (N170, line 20) to Z-45: its nine passes run 3 mm into the D36 shoulder at
    // Z-42; the deepest, at the root X27.546, 18 - 27.546 / 2 = 4.227 mm under it. Its
    // rapids back along X32 start inside the shoulder: (36 - 32) / 2 = 2 mm.
    let r = case_report("thread-into-shoulder", "crash.nc");
    assert_eq!(r.verdict, vpcut::Verdict::Fail);
    let g = of_kind(&r, FindingKind::Gouge);
    assert_eq!(g.len(), 1, "{:#?}", r.findings);
    assert_eq!(
        (g[0].file.as_deref(), g[0].line),
        (Some("crash.nc"), Some(20))
    );
    assert!(
        (g[0].value.unwrap() - (18.0 - 27.546 / 2.0)).abs() < 1e-6,
        "{:?}",
        g[0]
    );
    assert_eq!(g[0].pass, Some(9));
    let z = g[0].z_mm.unwrap();
    assert!((-45.0 - 1.0 / 6.0..-42.0).contains(&z), "{z}");
    let rapid = of_kind(&r, FindingKind::RapidCut);
    assert_eq!(rapid.len(), 1);
    assert!((rapid[0].value.unwrap() - 2.0).abs() < 1e-6);
    // Ending at Z-39.0 the run-out stays in the thread's section, clear of the face.
    let ok = case_report("thread-into-shoulder", "fixed.nc");
    assert_eq!(ok.verdict, vpcut::Verdict::Pass, "{:#?}", ok.findings);
    // Without [part] the crash's passes are only volume outside the compared thread.
    let job = case_job_text("thread-into-shoulder", "crash.nc", &|t| {
        let a = t.find("\n[part]").unwrap();
        let b = t.find("[[tool]]").unwrap();
        format!("{}{}", &t[..a], &t[b..])
    });
    let r = vpcut::simulate_report(&job, &SimOptions::default()).unwrap();
    assert!(of_kind(&r, FindingKind::Gouge).is_empty());
}

#[test]
fn the_part_is_checked_key_by_key() {
    let dir = root().join("tests/data/crash/thread-into-shoulder");
    let text = std::fs::read_to_string(dir.join("job.toml")).unwrap();
    let load = |f: &str| std::fs::read_to_string(dir.join(f)).ok();
    let profile =
        "profile = [[0.0, 26.0], [-2.0, 30.0], [-42.0, 30.0], [-42.0, 36.0], [-60.0, 36.0]]";
    for (to, says) in [
        (
            "profile = [[0.0, 26.0]]",
            ("part.profile", "at least two points"),
        ),
        (
            "profile = [[0.0, 26.0], [-2.0, 30.0], [-1.0, 30.0], [-60.0, 36.0]]",
            ("part.profile[2]", "in the order of z"),
        ),
        (
            "profile = [[0.0, 26.0], [-2.0, -30.0]]",
            ("part.profile[1]", "diameter of at least 0"),
        ),
        (
            "bore_profile = [[0.0, 10.0], [-5.0, 10.0]]",
            ("part.bore_profile", "blank.bore"),
        ),
        ("", ("part", "expected `profile`")),
        ("outline = [[0.0, 1.0]]", ("outline", "unknown")),
    ] {
        let t = text.replace(profile, to);
        let e = Job::from_toml_with(&t, "job.toml", &load)
            .unwrap_err()
            .to_string();
        assert!(e.contains(says.0) && e.contains(says.1), "{to}: {e}");
    }
}

/// One random case: a G76 or a G92 M30x2 program on a bar turned to d30 up to a D36
/// shoulder, its start point X, where the thread ends against the shoulder, and its first
/// cut.
#[derive(Debug)]
struct Case {
    g76: bool,
    /// The start point's X (the cycle's rapids return at it).
    x_start: f64,
    /// The shoulder's face (z).
    shoulder: f64,
    /// The thread's end (z).
    z_end: f64,
    /// G76: the first cut Q (mm); G92: the first pass's depth (mm).
    first: f64,
}

impl Case {
    /// The program.
    fn program(&self) -> String {
        let turn = format!(
            "T0101\nG97 S1000 M03\nG00 X38.0 Z0.0\nG01 X-1.0 F0.15\nG00 X30.0 Z1.0\nG01 Z{:.3} F0.2\nX37.0\nG00 X100.0 Z100.0\n",
            self.shoulder
        );
        let thread = if self.g76 {
            format!(
                "G76 P010060 Q100 R0.05\nG76 X27.546 Z{:.3} P1227 Q{} F2.0\n",
                self.z_end,
                (self.first * 1000.0).round()
            )
        } else {
            // The first pass at `first` under the crest (at most the root's 1.227), then the
            // rest of the depth in steps of 0.15 down to the root.
            let mut d = self.first.min(1.227);
            let mut s = format!("G92 X{:.3} Z{:.3} F2.0\n", 30.0 - 2.0 * d, self.z_end);
            while d < 1.227 - 1e-9 {
                d = (d + 0.15).min(1.227);
                s.push_str(&format!("X{:.3}\n", 30.0 - 2.0 * d));
            }
            s
        };
        format!(
            "{turn}T0303\nG97 S800 M03\nG00 X{:.3} Z5.0\n{thread}G00 X100.0 Z100.0\nM30\n",
            self.x_start
        )
    }

    /// The job: the bar, the part (d30 to the shoulder, D36 beyond), the tools (the
    /// insert stands 0.45 mm a pass).
    fn job(&self) -> Job {
        let text = format!(
            r#"
[blank]
diameter = 36.0
length = 61.0
z_front = 1.0
[thread]
form = "iso-metric"
major_diameter = 30.0
pitch = 2.0
length = 30.0
z_start = -3.0
[part]
profile = [[0.0, 30.0], [{s}, 30.0], [{s}, 36.0], [-60.0, 36.0]]
[[tool]]
id = 1
kind = "turning"
nose_radius = 0.0
edge_angles = [0.0, 85.0]
[[tool]]
id = 3
kind = "threading"
angle = 60.0
tip_flat = 0.3333333333
reference = "tip"
max_depth_per_pass = 0.45
[program]
file = "p.nc"
dialect = "fanuc"
[machine]
spindle_rpm = 800
[simulation]
axial_spacing = 0.02
angular_cells = 180
measure_generators = 2
"#,
            s = self.shoulder
        );
        let prog = self.program();
        Job::from_toml_with(&text, "job.toml", &move |f: &str| {
            (f == "p.nc").then(|| prog.clone())
        })
        .unwrap_or_else(|e| panic!("{self:?}: {e}"))
    }
}

#[test]
fn random_cycles_fail_exactly_where_a_rule_by_hand_says() {
    // The rule, derived by hand for these cases:
    // - a start point X under the crest's 30 returns along the bar under it: rapid_cut
    //   (30 - X) / 2 deep; at X30 exactly the tip grazes the crest: nothing;
    // - a thread ending past the shoulder's face runs into it (its tip at the root is
    //   18 - 13.773 under the D36) and its rapids back at X < 36 start inside it:
    //   a part gouge and a rapid_cut; ending 4 to 5 mm before the face, the insert's flank
    //   stands at least 13.773 + (4 - 1/6) cot 30 = 20.41 over the axis at the face, and
    //   the rapid back from X >= 30 reaches at most 1/6 + 3 tan 30 = 1.90 beyond its
    //   tip: nothing;
    // - the first chip: G76's first pass cuts min(Q, k - d) = min(Q, 1.177) under the
    //   crest (its later chips are smaller: 0.414 Q, or the 0.1 minimum cut, and 0.077,
    //   0.05 at the end); G92's the first depth (at most the root's 1.227), the later
    //   steps 0.15 or less: over the
    //   insert's 0.45 is a depth_per_pass error (a thread run into the shoulder also meets
    //   the shoulder's 3 mm above the crest: its chips there are not asserted, the gouge
    //   fails it anyway).
    // Everything else is a clean M30x2: fail exactly when one of these holds.
    let mut rng = crate::support::Rng(2801);
    let mut verdicts = [0usize; 2];
    for case in 0..48 {
        let g76 = case % 2 == 0;
        let x_start = match case % 3 {
            0 => rng.range(30.2, 33.0),
            1 => 30.0,
            _ => rng.range(28.0, 29.8),
        };
        let shoulder = rng.range(-50.0, -41.0);
        let into = rng.pick(&[false, true]);
        let z_end = if into {
            shoulder - rng.range(0.5, 3.0)
        } else {
            shoulder + rng.range(4.0, 5.0)
        };
        // First cuts on either side of the 0.45 limit, clear of it by more than the chip's
        // bound (0.0035).
        let first = if rng.pick(&[false, true]) {
            rng.range(0.15, 0.44)
        } else {
            rng.range(0.46, 1.3)
        };
        let first = (first * 1000.0).round() / 1000.0;
        let c = Case {
            g76,
            x_start: (x_start * 1000.0).round() / 1000.0,
            shoulder: (shoulder * 1000.0).round() / 1000.0,
            z_end: (z_end * 1000.0).round() / 1000.0,
            first,
        };
        let chip = if g76 {
            first.min(1.227 - 0.05)
        } else {
            first.min(1.227)
        };
        let want_rapid = c.x_start < 30.0 || into;
        let want_gouge = into;
        let want_chip = chip > 0.45;
        let r = vpcut::simulate_report(&c.job(), &SimOptions::default()).unwrap();
        let has = |k: FindingKind| r.findings.iter().any(|f| f.kind == k && f.is_error());
        let part_gouges = r
            .findings
            .iter()
            .filter(|f| f.kind == FindingKind::Gouge && f.turn.is_none())
            .count();
        assert_eq!(
            has(FindingKind::RapidCut),
            want_rapid,
            "{c:?}\n{:#?}",
            r.findings
        );
        assert_eq!(part_gouges > 0, want_gouge, "{c:?}\n{:#?}", r.findings);
        if !into {
            assert_eq!(
                has(FindingKind::DepthPerPass),
                want_chip,
                "{c:?}\n{:#?}",
                r.findings
            );
        }
        let want = if want_rapid || want_gouge || want_chip {
            vpcut::Verdict::Fail
        } else {
            vpcut::Verdict::Pass
        };
        assert_eq!(r.verdict, want, "{c:?}\n{:#?}", r.findings);
        verdicts[usize::from(want == vpcut::Verdict::Fail)] += 1;
        if c.x_start < 30.0 && !into {
            let d = r
                .findings
                .iter()
                .filter(|f| f.kind == FindingKind::RapidCut)
                .map(|f| f.value.unwrap())
                .fold(0.0, f64::max);
            assert!((d - (30.0 - c.x_start) / 2.0).abs() < 1e-6, "{c:?}: {d}");
        }
    }
    // Both verdicts are drawn (the seed's cases: clean ones and each kind of crash).
    assert!(verdicts[0] >= 5 && verdicts[1] >= 5, "{verdicts:?}");
}

#[test]
fn a_threading_inserts_plunge_and_radial_entry_are_crashes_at_their_blocks() {
    // On the 30 mm bar: G01 X29 at z -10 plunges the insert (30 - 29)/2 = 0.5 mm into it
    // (line 5); G32 from X32 Z-10 to X26 Z-10.5 goes 3 mm in for 0.5 along: a synchronised
    // radial entry whose tip reaches r 13, (30 - 26)/2 = 2 mm under the crest (line 7).
    // The rapid straight out after it (line 8) leaves its own groove: not a finding.
    let prog =
        "T0303\nG97 S500 M03\nG0 X32 Z5\nG0 Z-10\nG1 X29 F0.1\nG0 X32\nG32 X26 Z-10.5 F2.0\nG0 X32\nG0 Z5\nM30\n";
    let job = small_job(prog, "").unwrap_or_else(|e| panic!("{e}"));
    let r = vpcut::simulate_report(&job, &SimOptions::default()).unwrap();
    let hits = of_kind(&r, FindingKind::RapidCut);
    let got: Vec<(Option<usize>, f64)> = hits
        .iter()
        .map(|f| (f.line, (f.value.unwrap() * 1e6).round() / 1e6))
        .collect();
    assert_eq!(got, [(Some(5), 0.5), (Some(7), 2.0)], "{:#?}", r.findings);
    assert!(hits[0]
        .message
        .contains("a feed move of the threading insert T0303"));
    assert!(hits[1].message.contains("synchronised entry"));
}

//! A new user's trials (shop programs written from a drawing's words, as a CNC programmer
//! writes them): what they turned up, each as a class of cases against values derived by
//! hand or in closed form.

use crate::support::Rng;
use vpcut::{simulate, FindingKind, Job, Report, SimOptions};

/// A small ISO metric job on a `d` mm bar whose face is at `zf`, thread M`d`x2 over 8 mm,
/// one 60 deg insert (id 3), `program` in `dialect` (as `p.nc`), and `extra` added at the
/// end (a `[program]` key, say: the table is last).
fn job(d: f64, zf: f64, dialect: &str, program: &str, extra: &str) -> Job {
    let text = format!(
        r#"
[blank]
diameter = {d}
length = 30.0
z_front = {zf}
[thread]
form = "iso-metric"
major_diameter = {d}
pitch = 2.0
length = 8.0
[[tool]]
id = 3
kind = "threading"
angle = 60.0
tip_flat = 0.25
[simulation]
angular_cells = 72
axial_spacing = 0.05
measure_generators = 2
[program]
file = "p.nc"
dialect = "{dialect}"
{extra}
"#
    );
    let program = program.to_string();
    Job::from_toml_with(&text, "job.toml", &move |f: &str| {
        (f == "p.nc").then(|| program.clone())
    })
    .unwrap_or_else(|e| panic!("{e}\n{text}"))
}

fn report(job: &Job) -> Report {
    simulate(job, &SimOptions::default())
        .unwrap_or_else(|e| panic!("{e}"))
        .report
}

/// The rapid length of a path of (diameter, z) points, in the axial plane (mm).
fn path_length(points: &[(f64, f64)]) -> f64 {
    points
        .windows(2)
        .map(|w| (0.5 * (w[1].0 - w[0].0)).hypot(w[1].1 - w[0].1))
        .sum()
}

/// A shop program's way home: FANUC/GSK `G28 U0 W0` (and G30), Siemens `G74 X1=0 Z1=0`
/// (`G75`), LinuxCNC `G28` (`G30`), from a point clear of the part. Without `[program]
/// reference_point` the job puts its reference points clear of the blank (its diameter +
/// 100, its face + 100), not at the machine zero, which is the work zero on the part's
/// axis: the trial's `M30x2` program (`G28 U0. W0.` between its turning and its thread)
/// ran a rapid 12.9 mm into the part. The rapids home are exactly as long as that point
/// says (the cycle time's rapid seconds at the default 10000 mm/min), nothing meets the
/// part; a reference point given inside the part still sends them through it.
#[test]
fn going_home_without_a_reference_point_stays_clear_of_the_part() {
    let mut rng = Rng(2024);
    for case in 0..24 {
        let d = rng.range(10.0, 80.0).round();
        let zf = rng.range(-5.0, 5.0).round();
        let (x0, z0) = (
            d + rng.range(2.0, 20.0).round(),
            zf + rng.range(1.0, 20.0).round(),
        );
        let (xa, za, zt) = (d + 2.0, zf + 4.0, zf - 10.0);
        let xt = d - 1.3;
        let second = case % 2 == 1;
        let dialect = ["fanuc", "siemens-802d", "linuxcnc"][case % 3];
        let home = match (dialect, second) {
            ("fanuc", false) => "G28 U0. W0.",
            ("fanuc", true) => "G30 U0. W0.",
            ("siemens-802d", false) => "G74 X1=0 Z1=0",
            ("siemens-802d", true) => "G75 X1=0 Z1=0",
            (_, false) => "G28",
            (_, true) => "G30",
        };
        let program = match dialect {
            "fanuc" => format!(
                "O1\nG00 X{x0:.1} Z{z0:.1}\n{home}\nG97 S200 M03\nG00 X{xa:.1} Z{za:.1}\nG00 X{xt:.1}\nG32 Z{zt:.1} F2.\nG00 X{xa:.1}\n{home}\nM30\n"
            ),
            "siemens-802d" => format!(
                "G0 X{x0:.1} Z{z0:.1}\n{home}\nM3 S200\nG0 X{xa:.1} Z{za:.1}\nG0 X{xt:.1}\nG33 Z{zt:.1} K2\nG0 X{xa:.1}\n{home}\nM30\n"
            ),
            _ => format!(
                "G7 G21\nG0 X{x0:.1} Z{z0:.1}\n{home}\nM3 S200\nG0 X{xa:.1} Z{za:.1}\nG0 X{xt:.1}\nG33 Z{zt:.1} K2\nG0 X{xa:.1}\n{home}\nM2\n"
            ),
        };
        let h = (d + 100.0, zf + 100.0);
        let j = job(d, zf, dialect, &program, "");
        let r = report(&j);
        let cuts: Vec<_> = r
            .findings
            .iter()
            .filter(|f| f.kind == FindingKind::RapidCut)
            .collect();
        assert!(cuts.is_empty(), "case {case} ({dialect} {home}): {cuts:#?}");
        // The rapids: to the home and back to the thread's start, in to the thread, out,
        // and home again (the program's first move, from wherever the machine was, is not
        // counted).
        let rapid =
            path_length(&[(x0, z0), h, (xa, za), (xt, za)]) + path_length(&[(xt, zt), (xa, zt), h]);
        let ct = j.cycle_time.as_ref().expect("a lathe program's cycle time");
        let want = rapid / 10000.0 * 60.0;
        assert!(
            (ct.rapid - want).abs() < 1e-9 * want.max(1.0),
            "case {case} ({dialect} {home}): rapids {} s, the path home gives {want} s",
            ct.rapid
        );
        // The same program with the reference point on the part's axis inside it (where
        // the machine zero is when it is the work zero at a faced-off end): home runs
        // through the part.
        let key = if second {
            "second_reference_point"
        } else {
            "reference_point"
        };
        let inside = format!("{key} = {{ x = 0, z = {} }}", zf - 5.0);
        let j0 = job(d, zf, dialect, &program, &inside);
        let r0 = report(&j0);
        assert!(
            r0.findings.iter().any(|f| f.kind == FindingKind::RapidCut),
            "case {case} ({dialect} {home}) home in the part: {:#?}",
            r0.findings
        );
    }
}

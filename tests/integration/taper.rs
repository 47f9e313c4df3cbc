//! Issue 26: taper threads (NPT, ISO 7-1's R and Rc) judged by their taper gauge, against
//! a closed form. A cut by one full-depth tapered pass of a V insert of the thread's angle
//! (tip flat f) is a perfect taper thread: its grooves are the insert's profile, whose
//! walls keep their angle to the radial, and along the pitch cone (slope s on the radius)
//! a groove whose insert's root lies at diameter X is `A (1/(1 - k) + 1/(1 + k))` wide,
//! `A = f/2 + (R - X/2) tan b` at cone radius R, `k = s tan b` (b the half-angle): it is
//! half a pitch wide at `R = X/2 + (P/4 (1 - k^2) - f/2) cot b`. The pass is derived so
//! that this pitch cone lies `d` off the basic one on the diameter; the taper gauge (a
//! perfect one of the basic profile, screwed on hand-tight) then stops `16 d / P` turns
//! short of the part's gauge plane (1:16 on the diameter). Random sizes and stand-offs,
//! external and internal, placed on the cut (no `z_start`); the stand-off must be the
//! derived one within the stated resolution, and the verdict right.

use vpcut::{simulate_report, Job, SimOptions};

/// A small xorshift generator (seeded: the cases are the same every run).
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
    fn pick<'a>(&mut self, v: &[&'a str]) -> &'a str {
        v[((self.next() * v.len() as f64) as usize).min(v.len() - 1)]
    }
}

/// The job of one case: `designation` on the side `internal`, cut `turns_off` turns off
/// its gauge plane (positive: more material).
fn job(designation: &str, internal: bool, turns_off: f64) -> (Job, f64) {
    // The class's numbers, from a probe job (its blank large enough for any size).
    let probe_text = |blank: &str, pass: &str, flat: f64| {
        format!(
            "[blank]\n{blank}\nlength = 120.0\nz_front = 0.0\n\
             [thread]\ndesignation = \"{designation}\"\n{side}length = 40.0\n\
             [[tool]]\nid = 1\nkind = \"threading\"\nangle = {angle}\ntip_flat = {flat}\nreference = \"tip\"\n\
             {pass}\
             [simulation]\naxial_spacing = 0.02\nangular_cells = 90\ntolerance = 0.01\nmeasure_generators = 4\n",
            side = if internal { "side = \"internal\"\n" } else { "" },
            angle = if designation.contains("NPT") { 60.0 } else { 55.0 },
        )
    };
    let probe_blank = if internal {
        "diameter = 400.0\nbore = 1.0"
    } else {
        "diameter = 400.0"
    };
    let dummy = "[[pass]]\ntool = 1\nx = 10.0\nz_start = 0.0\nz_end = -1.0\nlead = 1.0\n";
    let probe = Job::from_toml(&probe_text(probe_blank, dummy, 0.1), "probe.toml")
        .unwrap_or_else(|e| panic!("{designation}: {e}"));
    let c = probe.thread_class.clone().expect("a class");
    let g = c.taper_gauge.expect("a taper gauge");
    let p = c.pitch;
    let b = 0.5 * c.flank_angle;
    let f = 0.1 * p;
    let k = b.tan() / 32.0;
    // The basic pitch cone: E at the gauge plane, `gauge_plane` into the part from the
    // face (z = 0); growing into the part outside, shrinking inside.
    let e = |z: f64| {
        let into = -z - g.gauge_plane;
        if internal {
            c.basic_pitch_diameter - into / 16.0
        } else {
            c.basic_pitch_diameter + into / 16.0
        }
    };
    let d = turns_off * p / 16.0;
    let off = 2.0 * (0.25 * p * (1.0 - k * k) - 0.5 * f) / b.tan();
    // The insert's root: the cone `d` bigger (outside) or smaller (inside) less `off`.
    let x = |z: f64| {
        if internal {
            e(z) - d + off
        } else {
            e(z) + d - off
        }
    };
    let length = g.length + 4.0 * p;
    let (zs, ze) = (2.0 * p, -(length + 3.0 * p));
    let blank = if internal {
        format!("diameter = {}\nbore = {}", e(0.0) + 20.0, x(ze) - 2.0 * p)
    } else {
        format!("diameter = {}", x(ze) + 2.0 * p)
    };
    let pass = format!(
        "[[pass]]\ntool = 1\nx = {}\nx_end = {}\nz_start = {zs}\nz_end = {ze}\nlead = {p}\n",
        x(zs),
        x(ze)
    );
    let text = probe_text(&blank, &pass, f).replace("length = 40.0", &format!("length = {length}"));
    let job = Job::from_toml(&text, "taper.toml").unwrap_or_else(|e| panic!("{designation}: {e}"));
    (job, g.tolerance_turns)
}

#[test]
fn the_taper_gauge_stands_off_as_the_closed_form_says() {
    let mut rng = Rng(0x7a9e_12c0_55aa_0101);
    let npt = [
        "1/8-27 NPT",
        "1/4-18 NPT",
        "3/8-18 NPT",
        "1/2-14 NPT",
        "3/4-14 NPT",
        "1-11.5 NPT",
        "2-11.5 NPT",
        "3-8 NPT",
    ];
    let iso = ["1/8", "1/4", "1/2", "3/4", "1", "1 1/2", "2 1/2", "4"];
    let mut verdicts = [0usize; 2];
    for case in 0..14 {
        let internal = case % 2 == 1;
        let designation = if case % 4 < 2 {
            rng.pick(&npt).to_string()
        } else {
            let size = rng.pick(&iso);
            if internal {
                format!("Rc{size}")
            } else {
                format!("R{size}")
            }
        };
        // A stand-off 0.1 turn or more from the limits (the resolution is a thousandth).
        let tol = if designation.contains("NPT") {
            1.0
        } else {
            // ISO 7-1: 1 to 1.5 turns (2 1/2 and over), 1.25 to 1.5 inside.
            2.0
        };
        let turns_off = loop {
            let t = (rng.next() * 2.0 - 1.0) * tol * 1.6;
            if ((t.abs() - 1.0).abs() > 0.1)
                && ((t.abs() - 1.25).abs() > 0.1)
                && ((t.abs() - 1.5).abs() > 0.1)
            {
                break t;
            }
        };
        let (job, allowed) = job(&designation, internal, turns_off);
        let report = simulate_report(&job, &SimOptions::default())
            .unwrap_or_else(|e| panic!("case {case} {designation}: {e}"));
        let g = report.gauge.as_ref().expect("a gauge section");
        let t = g.taper.expect("a taper gauge");
        assert_eq!(t.gauge, if internal { "plug" } else { "ring" });
        assert!(
            (t.stand_off_turns - turns_off).abs() <= t.resolution_turns + 1e-5,
            "case {case} {designation} (internal {internal}): stand-off {} vs {turns_off} (resolution {})",
            t.stand_off_turns,
            t.resolution_turns
        );
        assert!(t.resolution_turns < 0.01, "{}", t.resolution_turns);
        let ok = turns_off.abs() <= allowed;
        assert_eq!(
            g.verdict,
            if ok { "pass" } else { "fail" },
            "case {case}: {g:?}"
        );
        assert_eq!(
            report.verdict == vpcut::Verdict::Pass,
            ok,
            "case {case}: {:?}",
            report.findings
        );
        verdicts[usize::from(ok)] += 1;
    }
    assert!(verdicts.iter().all(|&n| n > 0), "{verdicts:?}");
}

/// A FANUC 0i program cutting 1/2-14 NPT with a two-block G76 whose R tapers the passes
/// (R = the radius at the start less that at the end: negative, the pipe growing towards
/// the chuck), placed on the cut: the stand-off is the one the final X and R were derived
/// for (as above: the passes at full depth put the 60 deg insert's profile on the pitch
/// cone `d` off the basic one; the cycle's flank infeed before them changes nothing), for
/// the basic size, 0.4 turns large (a pass) and 1.3 turns small (a failure).
#[test]
fn a_g76_taper_program_stands_off_as_derived() {
    let p = 25.4 / 14.0;
    let e0 = (0.840 - (0.05 * 0.840 + 1.1) / 14.0) * 25.4;
    let b = 30f64.to_radians();
    let f = 0.1 * p;
    let k = b.tan() / 32.0;
    let off = 2.0 * (0.25 * p * (1.0 - k * k) - 0.5 * f) / b.tan();
    let (zs, ze) = (5.0, -20.0);
    let run = |turns_off: f64| {
        let d = turns_off * p / 16.0;
        let x = |z: f64| e0 + (0.0 - z) / 16.0 + d - off;
        let r = 0.5 * (x(zs) - x(ze));
        let program = format!(
            "%\nO2001 (1/2-14 NPT)\nN10 G21 G18 G40 G99\nN20 T0101\nN30 G97 S400 M03\n\
             N40 G00 X26.0 Z{zs:.3}\nN50 G76 P010060 Q50 R0.02\n\
             N60 G76 X{:.4} Z{ze:.3} R{r:.4} P1200 Q350 F{p:.6}\nN70 G00 X60.0 Z60.0\nN80 M30\n%\n",
            x(ze)
        );
        let text = format!(
            "[blank]\ndiameter = {}\nlength = 60.0\nz_front = 0.0\n\
             [thread]\ndesignation = \"1/2-14 NPT\"\nlength = 14.0\n\
             [[tool]]\nid = 1\nkind = \"threading\"\nangle = 60.0\ntip_flat = {f}\nreference = \"tip\"\n\
             [program]\nfile = \"O2001.NC\"\ndialect = \"fanuc\"\n\
             [machine]\nspindle_rpm = 400\nmax_feed = 5000\nacceleration = 2000\n\
             [simulation]\naxial_spacing = 0.02\nangular_cells = 90\ntolerance = 0.01\nmeasure_generators = 4\n",
            x(ze) + 2.4
        );
        let load = |name: &str| (name == "O2001.NC").then(|| program.clone());
        let job = Job::from_toml_with(&text, "npt.toml", &load).unwrap_or_else(|e| panic!("{e}"));
        let report = simulate_report(&job, &SimOptions::default()).unwrap();
        let g = report.gauge.clone().expect("a gauge section");
        (report, g.taper.expect("a taper gauge"))
    };
    for turns_off in [0.0, 0.4, -1.3] {
        let (report, t) = run(turns_off);
        assert!(
            (t.stand_off_turns - turns_off).abs() <= t.resolution_turns + 1e-5,
            "{turns_off}: {t:?}"
        );
        assert_eq!(
            report.verdict == vpcut::Verdict::Pass,
            turns_off.abs() <= 1.0,
            "{turns_off}: {:?}",
            report.findings
        );
    }
}

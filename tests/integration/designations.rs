//! `[thread] designation` and `class`: scene jobs rewritten with the drawing's designation
//! give the thread of their explicit keys (and the class the scenes wrote by hand as
//! `pitch_diameter_limits`) and simulate alike; keys beside a designation override nothing
//! they contradict; the internal thread's tap-drill bore within D1.

use crate::support::{report_json, root, scene_text, small, with};
use vpcut::{simulate, Job, SimOptions, ThreadClass};

/// A job text with `[thread]`'s `remove` keys removed and `add` set (TOML literals).
fn rewrite(text: &str, remove: &[&str], add: &[(&str, &str)]) -> String {
    let mut doc: toml_edit::DocumentMut = text.parse().expect("valid TOML");
    let t = doc["thread"].as_table_mut().expect("a [thread] table");
    for k in remove {
        t.remove(k);
    }
    let mut out = doc.to_string();
    let edits: Vec<(&str, &str, &str)> = add.iter().map(|(k, v)| ("thread", *k, *v)).collect();
    out = with(&out, &edits);
    out
}

fn scene_job_text(name: &str, text: &str) -> Result<Job, vpcut::JobError> {
    let dir = root().join("scenes").join(name);
    let load = |f: &str| std::fs::read_to_string(dir.join(f)).ok();
    Job::from_toml_with(text, "job.toml", &load)
}

fn class(job: &Job) -> &ThreadClass {
    job.thread_class.as_ref().expect("a tolerance class")
}

/// A scene rewritten: its name, the `[thread]` keys the designation replaces, the
/// designation, and the scene's own `pitch_diameter_limits` where it wrote the class's.
type Rewrite = (
    &'static str,
    &'static [&'static str],
    &'static str,
    Option<[f64; 2]>,
);

#[test]
fn scene_jobs_with_a_designation_give_the_same_thread() {
    // (scene, keys the designation replaces, designation, the scene's own
    // `pitch_diameter_limits` when it wrote the class's by hand).
    let rows: [Rewrite; 6] = [
        (
            "iso-m20x2.5-radial",
            &["form", "major_diameter", "pitch"],
            "M20-6g",
            None,
        ),
        (
            "turned-m20x2.5-fanuc",
            &["form", "major_diameter", "pitch"],
            "M20x2.5",
            None,
        ),
        (
            "seed003-g76-2in-12tpi",
            &["form", "major_diameter", "pitch"],
            "2-12 UN-2A",
            None,
        ),
        (
            "seed004-tr100x12",
            &["form", "major_diameter", "pitch"],
            "Tr100x12",
            None,
        ),
        // The nut's crest is the drilled bore (18.38, inside 6H's D1 18.376..18.676): with
        // the class the bore is the crest without `minor_diameter`.
        (
            "seed001-m20x1.5-thread-mill",
            &[
                "form",
                "major_diameter",
                "pitch",
                "side",
                "minor_diameter",
                "pitch_diameter_limits",
            ],
            "M20x1.5-6H",
            Some([19.026, 19.216]),
        ),
        (
            "m20x1.5-external-comb-mill",
            &[
                "form",
                "major_diameter",
                "pitch",
                "side",
                "pitch_diameter_limits",
            ],
            "M20x1.5-6h",
            Some([18.886, 19.026]),
        ),
    ];
    for (scene, remove, designation, limits) in rows {
        let text = scene_text(scene);
        let before = scene_job_text(scene, &text).unwrap_or_else(|e| panic!("{scene}: {e}"));
        let new = rewrite(
            &text,
            remove,
            &[("designation", &format!("\"{designation}\""))],
        );
        let after = scene_job_text(scene, &new).unwrap_or_else(|e| panic!("{scene}: {e}"));
        assert!(
            same_thread(&basic(&after), &before.thread),
            "{scene}: {:?} vs {:?}",
            after.thread,
            before.thread
        );
        assert_eq!(after.form, before.form, "{scene}");
        assert_eq!(after.passes.len(), before.passes.len(), "{scene}");
        if let Some([lo, hi]) = limits {
            let c = class(&after);
            assert!(
                (c.pitch_diameter.min - lo).abs() < 1e-9
                    && (c.pitch_diameter.max - hi).abs() < 1e-9,
                "{scene}: {} gives {:?}, the scene wrote [{lo}, {hi}]",
                designation,
                c.pitch_diameter
            );
        }
        // The keys the designation fills may stay beside it when they agree.
        let both = rewrite(
            &text,
            &[],
            &[("designation", &format!("\"{designation}\""))],
        );
        let both = rewrite(&both, &["pitch_diameter_limits"], &[]);
        let again = scene_job_text(scene, &both).unwrap_or_else(|e| panic!("{scene}: {e}"));
        assert!(
            same_thread(&basic(&again), &before.thread),
            "{scene} with its keys beside"
        );
    }
}

/// The thread a classed job would have at the basic size: a classed job's ideal sits at
/// the middle of its pitch-diameter zone, its flanks moved away from the material by
/// `|d2 basic - d2 mid| / 2` (the groove at the same pitch line wider by that times the
/// flanks' widening, its root that much deeper), and a basic crest at the middle of its
/// diameter's zone.
fn basic(job: &Job) -> vpcut::ThreadSpec {
    let mut t = job.thread.clone();
    let Some(c) = &job.thread_class else {
        return t;
    };
    let mid = 0.5 * (c.pitch_diameter.min + c.pitch_diameter.max);
    let away = if c.internal {
        0.5 * (mid - c.basic_pitch_diameter)
    } else {
        0.5 * (c.basic_pitch_diameter - mid)
    };
    if let vpcut::WidthRule::Groove(w) = t.width {
        t.width = vpcut::WidthRule::Groove(w - away * (t.left_angle.tan() + t.right_angle.tan()));
    }
    // The root moved as far, into the part (the scenes give no minor diameter of an
    // external thread; a given one stays).
    t.root_radius += if c.internal { -away } else { away };
    let (crest, basic_crest) = if c.internal {
        (c.minor_diameter, c.basic_minor)
    } else {
        (c.major_diameter, c.basic_major)
    };
    if crest.min.is_finite()
        && crest.max.is_finite()
        && (2.0 * t.crest_radius - 0.5 * (crest.min + crest.max)).abs() < 1e-9
    {
        t.crest_radius = basic_crest / 2.0;
    }
    t
}

/// `a` is `b` but for the groove width's last bits (the move to the zone's middle and
/// back is not exact in floating point).
fn same_thread(a: &vpcut::ThreadSpec, b: &vpcut::ThreadSpec) -> bool {
    let mut a = a.clone();
    if let (vpcut::WidthRule::Groove(x), vpcut::WidthRule::Groove(y)) = (a.width, b.width) {
        if (x - y).abs() < 1e-12 {
            a.width = b.width;
        }
    }
    if (a.root_radius - b.root_radius).abs() < 1e-12 {
        a.root_radius = b.root_radius;
    }
    a == *b
}

#[test]
fn a_designation_only_thread_simulates_as_the_explicit_one() {
    // iso-m20x2.5-radial, small: the report of `designation = "M20x2.5-6g"` is the
    // report of the explicit keys with `class = "6g"`: the same thread, class and gauges.
    let text = small("iso-m20x2.5-radial");
    let new = rewrite(
        &text,
        &["form", "major_diameter", "pitch"],
        &[("designation", "\"M20x2.5-6g\"")],
    );
    let text = rewrite(&text, &[], &[("class", "\"6g\"")]);
    let run = |t: &str| {
        let job = Job::from_toml(t, "job.toml").unwrap_or_else(|e| panic!("{e}"));
        report_json(&simulate(&job, &SimOptions::default()).unwrap())
    };
    assert_eq!(run(&new), run(&text));
    let job = Job::from_toml(&new, "job.toml").unwrap();
    let c = class(&job);
    assert_eq!((c.class.as_str(), c.internal), ("6g", false));
    // The length of engagement (N up to 30 mm for M20x2.5) is at most the thread's 25 mm.
    assert!(
        (c.engagement_length - 25.0).abs() < 1e-9,
        "{}",
        c.engagement_length
    );
}

const NUT: &str = r#"
    [blank]
    diameter = 30.0
    bore = 10.7
    length = 30.0
    [thread]
    designation = "1/2-13 UNC-2B"
    length = 15.0
    [[tool]]
    id = 1
    kind = "threading"
    angle = 60.0
    tip_flat = 0.2
    reference = "tip"
    [process]
    kind = "radial"
    tool = 1
    layers = 3
    [simulation]
    angular_cells = 36
    axial_spacing = 0.05
    measure_generators = 2
"#;

#[test]
fn a_tap_drill_bore_within_d1_is_the_crest() {
    // 1/2-13 UNC-2B: D1 0.417..0.434 in (10.592..11.024 mm, ASME B1.1); its 27/64 in
    // (10.7 mm) tap drill is inside, above the basic minor 10.585 mm: accepted, the crest.
    let job = Job::from_toml(NUT, "nut.toml").unwrap_or_else(|e| panic!("{e}"));
    let c = class(&job);
    assert!(c.internal && c.minor_diameter.contains(10.7));
    assert!((job.thread.crest_radius - 10.7 / 2.0).abs() < 1e-12);
    // A bore over D1 max is refused, naming the limit; without a class the old rule holds
    // (the bore no larger than the basic minor diameter).
    let e = Job::from_toml(&NUT.replace("bore = 10.7", "bore = 11.1"), "nut.toml")
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("`blank.bore`") && e.contains("D1 max = 11.0236"),
        "{e}"
    );
    let plain = NUT.replace(
        "designation = \"1/2-13 UNC-2B\"",
        "side = \"internal\"\nform = \"unified\"\nmajor_diameter = 12.7\npitch = 1.9538461538461538",
    );
    let e = Job::from_toml(&plain, "nut.toml").unwrap_err().to_string();
    assert!(
        e.contains("`thread.minor_diameter`") && e.contains("no larger than its minor"),
        "{e}"
    );
}

#[test]
fn an_external_class_accepts_a_bar_turned_within_its_major_diameter() {
    // M20x2.5-6g: d 19.623..19.958; a 19.9 mm bar is a 6g bar, its crest the thread's.
    let text = small("iso-m20x2.5-radial");
    let new = rewrite(
        &text,
        &["form", "major_diameter", "pitch"],
        &[("designation", "\"M20x2.5-6g\"")],
    );
    let job = Job::from_toml(&with(&new, &[("blank", "diameter", "19.9")]), "j.toml").unwrap();
    assert!((job.thread.crest_radius - 19.9 / 2.0).abs() < 1e-12);
    let e = Job::from_toml(&with(&new, &[("blank", "diameter", "19.5")]), "j.toml")
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("`blank.diameter`") && e.contains("19.623"),
        "{e}"
    );
}

#[test]
fn contradictions_name_both_keys() {
    let base = small("iso-m20x2.5-radial");
    let des = |d: &str, extra: &[(&str, &str)]| {
        let mut add = vec![("designation", d)];
        add.extend_from_slice(extra);
        rewrite(&base, &["form", "major_diameter", "pitch"], &add)
    };
    let cases: Vec<(String, &[&str])> = vec![
        (
            des("\"M20x2.5-6g\"", &[("major_diameter", "21.0")]),
            &[
                "`thread.major_diameter`",
                "`major_diameter = 21`",
                "`designation = \"M20x2.5-6g\"`",
                "20 mm",
            ],
        ),
        (
            des("\"M20x2.5-6g\"", &[("pitch", "2.0")]),
            &["`thread.pitch`", "`pitch = 2`", "a pitch of 2.5 mm"],
        ),
        (
            des("\"M20x2.5-6g\"", &[("form", "\"unified\"")]),
            &["`thread.form`", "the form `iso-metric`"],
        ),
        (
            des("\"M20x2.5-6g\"", &[("side", "\"internal\"")]),
            &[
                "`thread.side`",
                "`side = \"internal\"`",
                "an external thread",
            ],
        ),
        (
            des("\"M20x2.5-6g\"", &[("hand", "\"left\"")]),
            &["`thread.hand`", "right-hand thread (no LH)"],
        ),
        (
            des("\"M20x2.5-6g-LH\"", &[("hand", "\"right\"")]),
            &["`thread.hand`", "left-hand thread (LH)"],
        ),
        (
            des("\"M20x2.5-6g\"", &[("starts", "2")]),
            &["`thread.starts`", "1 start"],
        ),
        (
            des("\"M20x2.5-6g\"", &[("flank_angle", "55.0")]),
            &["`thread.flank_angle`", "60 degrees"],
        ),
        (
            des(
                "\"M20x2.5-6g\"",
                &[("pitch", "{ first = 2.5, increment = 0.1, turns = 5 }")],
            ),
            &["`thread.pitch`", "pitch series contradicts"],
        ),
        (
            des("\"M20x2.5-6g\"", &[("class", "\"6g\"")]),
            &["`thread.class`", "both give the class"],
        ),
        (
            des(
                "\"M20x2.5-6g\"",
                &[("pitch_diameter_limits", "[18.2, 18.3]")],
            ),
            &["`thread.pitch_diameter_limits`", "not both"],
        ),
        (
            des("\"M20x2.5-6g\"", &[("class", "\"6g\"")]),
            &["write it in the designation"],
        ),
        (
            des("\"M20x2.5-6H/6g\"", &[]),
            &["`thread.designation`", "is a fit", "give `side"],
        ),
        (
            des("\"M20X2.5-6G\"", &[]),
            &["`thread.designation`", "capitals", "side"],
        ),
        (
            des("\"M20x2.5-6k\"", &[]),
            &["`thread.designation`", "expected e, f, g or h"],
        ),
        (
            des("\"M20x2.5 UNC\"", &[]),
            &["`thread.designation`", "expected"],
        ),
        (
            // The 20 mm bar is under the small end's major diameter (E0 + 0.8P = 20.71).
            des("\"1/2-14 NPT\"", &[]),
            &["`blank.diameter`", "1/2-14 NPT", "small end", "20.7"],
        ),
        (
            des("\"R1/2\"", &[("side", "\"internal\"")]),
            &["`thread.side`", "an external thread"],
        ),
        (
            des("\"Tr20x4-8c\"", &[]),
            &["`thread.designation`", "not in vpcut", "public"],
        ),
        (
            des("\"G3/4\"", &[("side", "\"external\"")]),
            &["`thread.side`", "an internal thread", "G1/2 A or G1/2 B"],
        ),
        (
            rewrite(&base, &["form"], &[]),
            &["`thread.form`", "expected `form`", "`designation`"],
        ),
        (
            rewrite(&base, &["major_diameter"], &[]),
            &["`thread.major_diameter`", "missing"],
        ),
        (
            rewrite(&base, &["pitch"], &[]),
            &["`thread.pitch`", "missing"],
        ),
        (
            rewrite(&base, &[], &[("class", "\"6H\""), ("side", "\"external\"")]),
            &["`thread.side`", "contradicts `class = \"6H\"`"],
        ),
        (
            rewrite(&base, &[], &[("class", "\"6d\"")]),
            &["`thread.class`", "expected e, f, g or h"],
        ),
        (
            rewrite(
                &base,
                &["form"],
                &[("form", "\"square\""), ("class", "\"6g\"")],
            ),
            &["`thread.class`", "not `square`"],
        ),
    ];
    for (text, want) in cases {
        let e = Job::from_toml(&text, "job.toml")
            .expect_err(&text)
            .to_string();
        for w in want {
            assert!(e.contains(w), "`{e}` does not say `{w}`");
        }
        assert!(!e.contains("Some(") && !e.contains("None"), "{e}");
    }
}

#[test]
fn sides_fits_and_the_class_key() {
    let base = small("iso-m20x2.5-radial");
    // A fit with the side: the external one here.
    let fit = rewrite(
        &base,
        &["form", "major_diameter", "pitch"],
        &[
            ("designation", "\"M20x2.5-6H/6g\""),
            ("side", "\"external\""),
        ],
    );
    let job = Job::from_toml(&fit, "j.toml").unwrap();
    assert_eq!(class(&job).class, "6g");
    // Keys the designation does not fix override its basic profile: the root here.
    let root = rewrite(
        &base,
        &["form", "major_diameter", "pitch"],
        &[
            ("designation", "\"M20x2.5-6g\""),
            ("minor_diameter", "17.0"),
        ],
    );
    let job = Job::from_toml(&root, "j.toml").unwrap_or_else(|e| panic!("{e}"));
    assert!((job.thread.root_radius - 8.5).abs() < 1e-12);
    // Capitals read by the side.
    let caps = rewrite(
        &base,
        &["form", "major_diameter", "pitch"],
        &[("designation", "\"M20X2.5-6G\""), ("side", "\"external\"")],
    );
    assert_eq!(class(&Job::from_toml(&caps, "j.toml").unwrap()).class, "6g");
    // `class = "6g"` with the explicit keys: the same limits as the designation.
    let key = with(&base, &[("thread", "class", "\"6g\"")]);
    let a = Job::from_toml(&key, "j.toml").unwrap();
    let b = Job::from_toml(
        &rewrite(
            &base,
            &["form", "major_diameter", "pitch"],
            &[("designation", "\"M20x2.5-6g\"")],
        ),
        "j.toml",
    )
    .unwrap();
    assert_eq!(class(&a).pitch_diameter, class(&b).pitch_diameter);
    assert_eq!(a.thread, b.thread);
    // A size the tables do not list (M23 x 2.5: 22.4 to 45 mm has no 2.5): ISO 965-1's
    // formulas.
    let odd = with(
        &base,
        &[
            ("thread", "class", "\"6g\""),
            ("thread", "major_diameter", "23.0"),
            ("blank", "diameter", "23.0"),
        ],
    );
    let c = Job::from_toml(&odd, "j.toml").unwrap_or_else(|e| panic!("{e}"));
    assert!(
        class(&c).source.contains("formulas"),
        "{}",
        class(&c).source
    );
    // A G thread: Whitworth 55°, simulated as a `v` form with ISO 228-1's basic profile.
    let g = r#"
        [blank]
        diameter = 20.955
        length = 30.0
        [thread]
        designation = "G1/2 A"
        length = 12.0
        [[tool]]
        id = 1
        kind = "threading"
        angle = 55.0
        tip_flat = 0.2
        reference = "tip"
        [process]
        kind = "radial"
        tool = 1
        layers = 3
        [simulation]
        angular_cells = 36
        axial_spacing = 0.05
        measure_generators = 2
    "#;
    let job = Job::from_toml(g, "j.toml").unwrap_or_else(|e| panic!("{e}"));
    assert!((job.thread.left_angle.to_degrees() - 27.5).abs() < 1e-9);
    assert!((job.thread.pitch_radius - 19.793 / 2.0).abs() < 1e-9);
    // The basic root (18.631), that is the ideal's at the middle of class A's pitch-diameter
    // zone: half the zone's distance below the basic pitch diameter deeper.
    let c = class(&job);
    let away = 0.5 * (c.basic_pitch_diameter - 0.5 * (c.pitch_diameter.min + c.pitch_diameter.max));
    assert!((job.thread.root_radius - (18.631 / 2.0 - away)).abs() < 1e-9);
    assert_eq!(c.class, "A");
}

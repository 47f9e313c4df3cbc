//! Issue 28, tool assemblies: a threading insert's holder reaching a shoulder, a boring bar
//! in a bore too small for it, a holder running into the chuck's jaws: each a `collision`
//! error at its block, its depth against a closed-form clearance; no collision where the
//! clearance is positive.
//!
//! The part turns, so a holder meets it where it comes nearer the axis than the stock (a
//! shank's bottom face: the tip's radius plus its `clearance`) or, in a bore, farther from
//! it (a bar's farthest point: `d/2 + |r - reach|` for the tip at radius `r`).

use crate::support::Rng;
use vpcut::{simulate_report, FindingKind, Job, Report, SimOptions};

fn job(text: &str, program: String) -> Job {
    Job::from_toml_with(text, "holder.toml", &move |f: &str| {
        (f == "O2801.NC").then(|| program.clone())
    })
    .unwrap_or_else(|e| panic!("{e}"))
}

fn collisions(r: &Report) -> Vec<&vpcut::Finding> {
    r.findings
        .iter()
        .filter(|f| f.kind == FindingKind::Collision)
        .collect()
}

/// Outside: a 34 mm bar `length` long from Z0, turned to 30 mm up to `z_turn` (a sharp tool), an M30x2 G76 to
/// Z-36 (root X27.546) with T0303, whose holder is `holder`; `machine` is added to
/// `[machine]`. The G76's second block is line 15.
fn outside(z_turn: f64, length: f64, holder: &str, machine: &str) -> Report {
    let program = format!(
        "%\nO2801\nN10 G21 G18 G40 G99\nN20 T0101\nN30 G97 S800 M03\nN40 G00 X30.0 Z1.0\n\
         N50 G01 Z{z_turn:.3} F0.1\nN60 X36.0\nN70 G00 X100.0 Z100.0\nN80 T0303\n\
         N90 G97 S600 M03\nN100 G00 X32.0 Z5.0\nN110 G76 P010060 Q100 R0.05\n\
         (SECOND BLOCK)\nN120 G76 X27.546 Z-36.0 P1227 Q400 F2.0\nN130 G00 X100.0 Z100.0\nN140 M30\n%\n"
    );
    let text = format!(
        r#"
[blank]
diameter = 34.0
length = {length}
[thread]
form = "iso-metric"
major_diameter = 30.0
pitch = 2.0
length = 32.0
[[tool]]
id = 1
kind = "turning"
nose_radius = 0.0
[[tool]]
id = 3
kind = "threading"
angle = 60.0
tip_flat = 0.3333333333
reference = "tip"
holder = {holder}
[program]
file = "O2801.NC"
dialect = "fanuc"
[machine]
spindle_rpm = 600
max_feed = 5000
{machine}
[simulation]
axial_spacing = 0.02
angular_cells = 72
measure_generators = 2
"#
    );
    simulate_report(&job(&text, program), &SimOptions::default()).unwrap()
}

/// The shank's -z face passes the D34 shoulder at Z-40 when it reaches `left > 4` mm past
/// the tip at Z-36; its bottom face, `clearance` over the final pass's tip (27.546 / 2 =
/// 13.773), then lies `17 - 13.773 - clearance = 3.227 - clearance` under the shoulder's
/// radius. The crest (15) is under the bottom face for every clearance over 1.227.
#[test]
fn a_holder_reaching_the_shoulder_on_the_last_pass_is_a_collision_at_its_block() {
    let mut rng = Rng(0x2828);
    let mut seen = (0, 0);
    for _ in 0..14 {
        let left = rng.range(2.5, 6.0);
        let clearance = rng.range(1.3, 4.5);
        // Clear of the cells' rounding at the edges of the rule.
        if (left - 4.0).abs() < 0.05 || (clearance - 3.227).abs() < 0.02 {
            continue;
        }
        let r = outside(
            -40.0,
            60.0,
            &format!(
                "{{ kind = \"shank\", left = {left}, right = 25.0, clearance = {clearance} }}"
            ),
            "",
        );
        let c = collisions(&r);
        if left > 4.0 && clearance < 3.227 {
            seen.0 += 1;
            assert_eq!(c.len(), 1, "left {left} clearance {clearance}: {c:#?}");
            assert_eq!(c[0].line, Some(15));
            let depth = c[0].value.unwrap();
            assert!(
                (depth - (3.227 - clearance)).abs() < 1e-3,
                "left {left} clearance {clearance}: {depth}"
            );
            assert!(c[0].message.contains("holder"), "{}", c[0].message);
        } else {
            seen.1 += 1;
            assert!(c.is_empty(), "left {left} clearance {clearance}: {c:#?}");
        }
    }
    assert!(seen.0 >= 3 && seen.1 >= 3, "{seen:?}");
}

/// The chuck's jaws (D50 from Z-45.5 back) and a 45 mm bar turned to 30 mm over its
/// length: the shank's -z face passes Z-45.5 when `left > 9.5`, its bottom
/// `25 - 13.773 - clearance` under the jaws' radius. The tips (the turning tool's at
/// Z-45) stay clear of them.
#[test]
fn a_holder_running_into_the_jaws_is_a_collision_at_its_block() {
    let chuck = "chuck = [[-45.5, 50.0], [-70.0, 50.0]]";
    for (left, clearance, hit) in [
        (10.5, 3.0, Some(25.0 - 13.773 - 3.0)),
        (10.5, 12.0, None),
        (9.0, 3.0, None),
        (12.0, 8.0, Some(25.0 - 13.773 - 8.0)),
    ] {
        let r = outside(
            -45.0,
            45.0,
            &format!(
                "{{ kind = \"shank\", left = {left}, right = 25.0, clearance = {clearance} }}"
            ),
            chuck,
        );
        let c = collisions(&r);
        match hit {
            Some(depth) => {
                assert_eq!(c.len(), 1, "{left} {clearance}: {c:#?}");
                assert_eq!(c[0].line, Some(15));
                assert!(c[0].message.contains("chuck"), "{}", c[0].message);
                let v = c[0].value.unwrap();
                assert!(
                    (v - depth).abs() < 1e-3,
                    "{left} {clearance}: {v} vs {depth}"
                );
            }
            None => assert!(c.is_empty(), "{left} {clearance}: {c:#?}"),
        }
    }
}

/// Inside: an M30x2 nut, a tube D50 with the basic minor diameter's bore (27.834) from Z0
/// to Z-40, a G76 from X26 Z5 to Z-20 (final X30: the tip at radius 13 after each pass's
/// retract, 15 on the last pass), the insert on a bar of diameter `2b` whose centre line is
/// `reach` from the tip, reaching 60 mm out of the bore. The bar's farthest point lies
/// `b + |r - reach|` from the axis; in the bore (its span reaches the wall once the tip is
/// past Z0) that is largest at r = 13 or r = 15, and the bore's wall stays at its radius
/// 13.917 (the passes leave the crest): the deepest collision is
/// `max(b + |13 - reach|, b + |15 - reach|) - 13.917`, when positive.
#[test]
fn a_boring_bar_in_a_bore_too_small_for_it_is_a_collision_at_its_block() {
    let program = "%\nO2801\nN10 G21 G18 G40 G99\nN20 T0303\nN30 G97 S600 M03\nN40 G00 X26.0 Z5.0\n\
                   N50 G76 P010060 Q100 R0.05\nN60 G76 X30.0 Z-20.0 P1083 Q400 F2.0\nN70 G00 Z50.0\nN80 M30\n%\n";
    let mut rng = Rng(0xba5e);
    let mut seen = (0, 0);
    for _ in 0..16 {
        let b = rng.range(4.0, 12.0);
        let reach = rng.range(4.0, 18.0);
        let want = (b + (13.0 - reach).abs()).max(b + (15.0 - reach).abs()) - 13.917;
        if want.abs() < 0.01 {
            continue;
        }
        let text = format!(
            r#"
[blank]
diameter = 50.0
bore = 27.834
length = 40.0
[thread]
form = "iso-metric"
major_diameter = 30.0
pitch = 2.0
side = "internal"
length = 16.0
[[tool]]
id = 3
kind = "threading"
angle = 60.0
tip_flat = 0.25
reference = "tip"
holder = {{ kind = "bar", diameter = {d}, reach = {reach}, length = 60.0 }}
[program]
file = "O2801.NC"
dialect = "fanuc"
[machine]
spindle_rpm = 600
max_feed = 5000
[simulation]
axial_spacing = 0.02
angular_cells = 72
measure_generators = 2
"#,
            d = 2.0 * b
        );
        let r = simulate_report(&job(&text, program.to_string()), &SimOptions::default()).unwrap();
        let c = collisions(&r);
        if want > 0.0 {
            seen.0 += 1;
            assert_eq!(c.len(), 1, "b {b} reach {reach}: {c:#?}");
            assert_eq!(c[0].line, Some(8));
            let v = c[0].value.unwrap();
            assert!(
                (v - want).abs() < 1e-3,
                "b {b} reach {reach}: {v} vs {want}"
            );
            assert!(c[0].message.contains("boring bar"), "{}", c[0].message);
        } else {
            seen.1 += 1;
            assert!(c.is_empty(), "b {b} reach {reach}: {c:#?}");
        }
    }
    assert!(seen.0 >= 3 && seen.1 >= 3, "{seen:?}");
}

/// A holder of the wrong kind for where its tool cuts, or with a missing key, is refused
/// naming the key.
#[test]
fn holders_are_checked_key_by_key() {
    let base = |holder: &str, side: &str| {
        format!(
            "[blank]\ndiameter = 50.0\nbore = 27.834\nlength = 40.0\n[thread]\nform = \"iso-metric\"\n\
             major_diameter = 30.0\npitch = 2.0\nside = \"{side}\"\nlength = 16.0\n[[tool]]\nid = 3\n\
             kind = \"threading\"\nangle = 60.0\nholder = {holder}\n[program]\nfile = \"O2801.NC\"\n\
             dialect = \"fanuc\"\n"
        )
    };
    for (holder, side, key) in [
        (
            "{ kind = \"shank\", left = 1.0, right = 2.0, clearance = 1.0 }",
            "internal",
            "tool[0].holder.kind",
        ),
        (
            "{ kind = \"bar\", diameter = 10.0, reach = 8.0, length = 50.0 }",
            "external",
            "tool[0].holder.kind",
        ),
        (
            "{ kind = \"bar\", reach = 8.0, length = 50.0 }",
            "internal",
            "tool[0].holder.diameter",
        ),
        (
            "{ kind = \"shank\", left = 1.0, clearance = 1.0 }",
            "external",
            "tool[0].holder.right",
        ),
        (
            "{ kind = \"shank\", left = 1.0, right = 2.0, clearance = 1.0, reach = 3.0 }",
            "external",
            "tool[0].holder.reach",
        ),
        (
            "{ kind = \"shank\", left = -3.0, right = 2.0, clearance = 1.0 }",
            "external",
            "tool[0].holder.right",
        ),
        (
            "{ kind = \"shank\", left = 1.0, right = 2.0, clearance = -1.0 }",
            "external",
            "tool[0].holder.clearance",
        ),
    ] {
        let text = base(holder, side);
        let err = Job::from_toml_with(&text, "holder.toml", &|_: &str| Some("G00 X30 Z5\n".into()))
            .err()
            .unwrap_or_else(|| panic!("{holder} accepted"));
        let msg = err.to_string();
        assert!(msg.contains(key), "{holder}: {msg}");
    }
}

/// No false collision on the scenes: every lathe scene whose program drives its tools, with
/// holders as a catalogue would size them (a turning tool's shank starting 0.5 mm to the +z
/// side of its tip and 8 mm above it, as a 95 deg holder's; an insert's 2 mm above the
/// thread's depth, flush with its tip), meets nothing: no `collision` finding.
#[test]
fn catalogue_holders_meet_nothing_on_the_lathe_scenes() {
    let mut checked = 0;
    for name in crate::support::scenes() {
        let text = crate::support::small(&name);
        if !text.contains("[program]") || text.contains("kind = \"mill\"") {
            continue;
        }
        let depth = crate::support::scene_job(&name).thread.depth();
        let mut doc: toml_edit::DocumentMut = text.parse().unwrap();
        let Some(tools) = doc.get_mut("tool").and_then(|t| t.as_array_of_tables_mut()) else {
            continue;
        };
        for t in tools.iter_mut() {
            let kind = t
                .get("kind")
                .and_then(|k| k.as_str())
                .unwrap_or("")
                .to_string();
            let holder = match kind.as_str() {
                "turning" => {
                    "{ kind = \"shank\", left = -0.5, right = 25.0, clearance = 8.0 }".to_string()
                }
                "threading" | "grooving" | "trapezoidal" | "mesh" => format!(
                    "{{ kind = \"shank\", left = 0.0, right = 25.0, clearance = {} }}",
                    depth + 2.0
                ),
                _ => continue,
            };
            let v: toml_edit::Item = format!("x = {holder}")
                .parse::<toml_edit::DocumentMut>()
                .unwrap()["x"]
                .clone();
            t.insert("holder", v);
        }
        let dir = crate::support::root().join("scenes").join(&name);
        let load = |f: &str| std::fs::read_to_string(dir.join(f)).ok();
        let job = Job::from_toml_with(&doc.to_string(), "job.toml", &load)
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        let r = simulate_report(&job, &SimOptions::default()).unwrap();
        assert!(collisions(&r).is_empty(), "{name}: {:#?}", collisions(&r));
        checked += 1;
    }
    assert!(checked >= 7, "{checked} lathe scenes with programs");
}

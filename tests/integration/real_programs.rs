//! Issue 17 ("real programs run end to end"): `tests/data/programs/` holds threading
//! programs written in the style of public ones (see its README.md); each runs strictly
//! (every word understood, no warning) and makes the number of thread moves derived by hand
//! in the README.

use vpcut::{
    interpret_with, DecimalPoint, Dialect, GcodeSystem, MoveKind, NcOptions, Settings, Source,
};

/// (file, dialect, G-code system, thread moves)
const CORPUS: [(&str, Dialect, GcodeSystem, usize); 11] = [
    (
        "lcnc-pathpilot-g76.ngc",
        Dialect::Linuxcnc,
        GcodeSystem::A,
        14,
    ),
    (
        "lcnc-gui-macro-g33.ngc",
        Dialect::Linuxcnc,
        GcodeSystem::A,
        5,
    ),
    ("lcnc-offsets-g92.ngc", Dialect::Linuxcnc, GcodeSystem::A, 4),
    ("haas-g76-oneblock.nc", Dialect::Fanuc, GcodeSystem::A, 17),
    (
        "fanuc-0t-g76-increment.nc",
        Dialect::Fanuc,
        GcodeSystem::A,
        10,
    ),
    ("fanuc-tape-eob.nc", Dialect::Fanuc, GcodeSystem::A, 9),
    ("fanuc-one-line-tape.nc", Dialect::Fanuc, GcodeSystem::A, 11),
    ("fanuc-system-b.nc", Dialect::Fanuc, GcodeSystem::B, 4),
    ("fanuc-system-c.nc", Dialect::Fanuc, GcodeSystem::C, 4),
    ("gsk-g32-passes.nc", Dialect::Gsk980, GcodeSystem::A, 3),
    (
        "siemens-802d-g33.mpf",
        Dialect::Siemens802d,
        GcodeSystem::A,
        4,
    ),
];

#[test]
fn every_corpus_program_runs_strictly_with_its_thread_moves() {
    let dir = crate::support::root().join("tests/data/programs");
    let readme = std::fs::read_to_string(dir.join("README.md")).unwrap();
    let mut files: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n != "README.md")
        .collect();
    files.sort();
    let mut listed: Vec<String> = CORPUS.iter().map(|c| c.0.to_string()).collect();
    listed.sort();
    assert_eq!(files, listed, "every program of the corpus is tested");
    for (file, dialect, system, threads) in CORPUS {
        assert!(readme.contains(file), "README.md describes {file}");
        let text = std::fs::read_to_string(dir.join(file)).unwrap();
        let src = Source {
            name: file.into(),
            text,
        };
        // Two programs write plain numbers in mm (`G0 X30 Z5`, `F2`): a machine with
        // calculator-type decimal-point input (README.md).
        let calculator = ["fanuc-one-line-tape.nc", "gsk-g32-passes.nc"].contains(&file);
        let opts = NcOptions {
            strict: true,
            settings: Settings {
                gcode_system: system,
                decimal_point: if calculator {
                    DecimalPoint::Calculator
                } else {
                    DecimalPoint::Standard
                },
                ..Settings::default()
            },
            ..NcOptions::default()
        };
        let t = interpret_with(&src, dialect, &|_| None, &opts)
            .unwrap_or_else(|e| panic!("{file}:\n{e}"));
        assert!(t.warnings.is_empty(), "{file}: {:?}", t.warnings);
        let n = t
            .moves
            .iter()
            .filter(|m| m.kind == MoveKind::Thread)
            .count();
        assert_eq!(n, threads, "{file}: thread moves");
    }
}

/// Before issue 17 a FANUC tape whose blocks end in `;` on one line read as one comment:
/// nothing ran. Now it runs, and a system-B program read in a system A that the job names
/// is refused by name (strict). Issue 27: with no system named, the program's system is
/// read from it: the same moves as with `gcode_system = "B"`, and one warning naming it.
#[test]
fn the_corpus_needs_what_issue_17_added() {
    let dir = crate::support::root().join("tests/data/programs");
    let text = std::fs::read_to_string(dir.join("fanuc-system-b.nc")).unwrap();
    let src = Source {
        name: "fanuc-system-b.nc".into(),
        text,
    };
    let with = |system: Option<GcodeSystem>, strict: bool| NcOptions {
        strict,
        settings: Settings {
            gcode_system: system.unwrap_or(GcodeSystem::A),
            gcode_system_named: system.is_some(),
            ..Settings::default()
        },
        ..NcOptions::default()
    };
    let named_a = with(Some(GcodeSystem::A), true);
    assert!(interpret_with(&src, Dialect::Fanuc, &|_| None, &named_a).is_err());
    let read = interpret_with(&src, Dialect::Fanuc, &|_| None, &with(None, false)).unwrap();
    let named_b = interpret_with(
        &src,
        Dialect::Fanuc,
        &|_| None,
        &with(Some(GcodeSystem::B), false),
    )
    .unwrap();
    assert_eq!(read.moves, named_b.moves);
    assert!(read.moves.iter().any(|m| m.kind == MoveKind::Thread));
    let said: Vec<&str> = read.warnings.iter().map(|w| w.message.as_str()).collect();
    assert_eq!(said.len(), named_b.warnings.len() + 1, "{said:?}");
    assert!(
        said[0].starts_with("read in FANUC G-code system B"),
        "{said:?}"
    );
}

/// `vpcut toolpath` runs the corpus with its flags: the G-code system, and the reference
/// point G28 goes to (the corpus's Haas program ends with `G28 U0. W0.`).
#[test]
fn toolpath_flags_gcode_system_and_reference_point() {
    let dir = crate::support::root().join("tests/data/programs");
    let run = |args: &[&str]| {
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_vpcut"))
            .arg("toolpath")
            .args(args)
            .output()
            .unwrap();
        (
            out.status.code(),
            String::from_utf8_lossy(&out.stdout).into_owned(),
            String::from_utf8_lossy(&out.stderr).into_owned(),
        )
    };
    let b = dir.join("fanuc-system-b.nc");
    let b = b.to_str().unwrap();
    let (code, csv, err) = run(&[b, "--dialect", "fanuc", "--gcode-system", "B", "--strict"]);
    assert_eq!(code, Some(0), "{err}");
    assert_eq!(csv.lines().filter(|l| l.contains(",thread,")).count(), 4);
    let (code, _, err) = run(&[b, "--dialect", "fanuc", "--gcode-system", "D"]);
    assert_eq!(code, Some(2), "{err}");
    assert!(err.contains("expected A, B or C"), "{err}");
    let haas = dir.join("haas-g76-oneblock.nc");
    let haas = haas.to_str().unwrap();
    let (code, csv, err) = run(&[haas, "--dialect", "fanuc", "--reference-point", "250,-10.5"]);
    assert_eq!(code, Some(0), "{err}");
    let last = csv.lines().last().unwrap();
    assert!(last.contains(",rapid,250,125,-10.5,"), "{last}");
    let (code, _, err) = run(&[haas, "--dialect", "fanuc", "--reference-point", "250"]);
    assert_eq!(code, Some(2), "{err}");
    assert!(err.contains("expected X,Z"), "{err}");
}

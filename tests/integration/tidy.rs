//! Project hygiene: every source file has module docs; scenes and goldens correspond.

use crate::support::{root, scenes};

fn rust_files(dir: &std::path::Path, out: &mut Vec<std::path::PathBuf>) {
    for e in std::fs::read_dir(dir).unwrap().flatten() {
        let p = e.path();
        if p.is_dir() {
            rust_files(&p, out);
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
}

#[test]
fn every_source_file_starts_with_module_docs() {
    let mut files = Vec::new();
    for d in ["src", "tests", "benches"] {
        rust_files(&root().join(d), &mut files);
    }
    let missing: Vec<String> = files
        .iter()
        .filter(|p| !std::fs::read_to_string(p).unwrap().starts_with("//!"))
        .map(|p| p.display().to_string())
        .collect();
    assert!(missing.is_empty(), "no //! docs on line 1: {missing:?}");
}

#[test]
fn scenes_and_goldens_correspond() {
    let scenes = scenes();
    let mut goldens: Vec<String> = std::fs::read_dir(root().join("goldens"))
        .unwrap()
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .collect();
    goldens.sort();
    assert_eq!(
        scenes, goldens,
        "every scene has goldens/<scene>/ and no golden is orphaned"
    );
    for s in &scenes {
        let dir = root().join("scenes").join(s);
        assert!(
            dir.join("README.md").exists(),
            "scenes/{s} needs a README.md saying what it cuts and why"
        );
    }
}

#[test]
fn no_io_in_the_geometry_core() {
    for f in [
        "model", "kernel", "analysis", "gen", "output", "report", "pipeline", "job", "toolpath",
        "diag", "nc",
    ] {
        // A module is `src/<f>.rs` or a folder `src/<f>/` of files.
        let file = root().join("src").join(format!("{f}.rs"));
        let mut files = Vec::new();
        if file.exists() {
            files.push(file);
        } else {
            rust_files(&root().join("src").join(f), &mut files);
        }
        assert!(!files.is_empty(), "src/{f}.rs or src/{f}/ is missing");
        for p in files {
            let text = std::fs::read_to_string(&p).unwrap();
            assert!(
                !text.contains("std::fs") && !text.contains("println!"),
                "{} does IO",
                p.display()
            );
        }
    }
}

//! Project hygiene: every source file has module docs; scenes and goldens correspond; the
//! library's stages use only the stages before them and do no IO; no file grows too long.

use crate::support::{root, scenes};

fn rust_files(dir: &std::path::Path, out: &mut Vec<std::path::PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for e in entries.flatten() {
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

/// The library's stages, lowest first: a stage may use only the stages before it (and
/// itself), so there is no import cycle between them and each can be read without the
/// ones after it. `lib.rs` only declares and re-exports them; `main.rs` and `cli/` are the
/// binary.
const LAYERS: [&str; 11] = [
    "diag", "model", "kernel", "nc", "analysis", "gen", "toolpath", "job", "report", "pipeline",
    "output",
];

/// The library's source files, each with its stage (`None` for `lib.rs`).
fn library_files() -> Vec<(Option<&'static str>, std::path::PathBuf)> {
    let src = root().join("src");
    let mut out = vec![(None, src.join("lib.rs"))];
    for stage in LAYERS {
        let mut files = Vec::new();
        rust_files(&src.join(stage), &mut files);
        let file = src.join(format!("{stage}.rs"));
        if file.exists() {
            files.push(file);
        }
        assert!(!files.is_empty(), "src/{stage}/ is missing");
        files.sort();
        out.extend(files.into_iter().map(|f| (Some(stage), f)));
    }
    let mut all = Vec::new();
    rust_files(&src, &mut all);
    let binary = |p: &std::path::Path| p == src.join("main.rs") || p.starts_with(src.join("cli"));
    let listed: Vec<_> = out.iter().map(|(_, p)| p.clone()).collect();
    let strays: Vec<_> = all
        .iter()
        .filter(|p| !binary(p) && !listed.contains(p))
        .collect();
    assert!(strays.is_empty(), "files outside the stages: {strays:?}");
    out
}

/// A file's code without comments and without its `#[cfg(test)]` module (tests may build
/// their fixtures with later stages).
fn code(text: &str) -> String {
    let end = text.find("#[cfg(test)]\nmod ").unwrap_or(text.len());
    text[..end]
        .lines()
        .map(|l| match l.find("//") {
            Some(i) => &l[..i],
            None => l,
        })
        .collect::<Vec<_>>()
        .join("\n")
}

/// The stages a piece of code names with `crate::<stage>`.
fn stages_used(code: &str) -> Vec<&'static str> {
    LAYERS
        .iter()
        .copied()
        .filter(|s| {
            code.match_indices(&format!("crate::{s}")).any(|(i, m)| {
                !code[i + m.len()..].starts_with(|c: char| c.is_alphanumeric() || c == '_')
            })
        })
        .collect()
}

#[test]
fn stages_use_only_the_stages_before_them() {
    let mut wrong = Vec::new();
    for (stage, p) in library_files() {
        let Some(stage) = stage else { continue };
        let rank = LAYERS.iter().position(|s| *s == stage).unwrap();
        let text = std::fs::read_to_string(&p).unwrap();
        for used in stages_used(&code(&text)) {
            if LAYERS.iter().position(|s| *s == used).unwrap() > rank {
                wrong.push(format!("{} ({stage}) uses crate::{used}", p.display()));
            }
        }
    }
    assert!(wrong.is_empty(), "layer violations:\n{}", wrong.join("\n"));
}

#[test]
fn the_layer_check_sees_a_violation() {
    // The checker itself: a use of a later stage is found, a comment or a longer name is not.
    assert_eq!(stages_used("use crate::job::Job;"), ["job"]);
    assert!(stages_used(&code("// crate::job\nuse crate::jobs;")).is_empty());
    assert_eq!(
        stages_used(&code(
            "use crate::model::x;\n#[cfg(test)]\nmod tests { crate::output }"
        )),
        ["model"]
    );
}

#[test]
fn lib_rs_is_thin_and_no_file_is_long() {
    let src = root().join("src");
    let lib = std::fs::read_to_string(src.join("lib.rs")).unwrap();
    assert!(
        lib.lines().count() <= 250,
        "src/lib.rs has {} lines",
        lib.lines().count()
    );
    assert!(
        !code(&lib).contains("fn "),
        "src/lib.rs declares and re-exports; its functions belong to a stage"
    );
    let mut files = Vec::new();
    rust_files(&src, &mut files);
    let long: Vec<String> = files
        .iter()
        .filter_map(|p| {
            let n = std::fs::read_to_string(p).unwrap().lines().count();
            (n > 1200).then(|| format!("{} ({n} lines)", p.display()))
        })
        .collect();
    assert!(long.is_empty(), "files over 1200 lines: {long:?}");
}

#[test]
fn no_io_in_the_library() {
    // Files, the terminal, the environment and processes are the binary's (`main.rs`,
    // `cli/`): the library takes text and returns values.
    // The one exception: the renderer picks its GPU adapter by `WGPU_ADAPTER_NAME`, as
    // wgpu itself reads `WGPU_BACKEND`.
    let allowed =
        |p: &std::path::Path, io: &str| io == "std::env" && p.ends_with("src/output/render/gpu.rs");
    for (_, p) in library_files() {
        let text = code(&std::fs::read_to_string(&p).unwrap());
        for io in [
            "std::fs",
            "std::env",
            "std::process",
            "stdout()",
            "stderr()",
            "println!",
            "eprintln!",
            "print!(",
            "File::",
        ] {
            assert!(
                !text.contains(io) || allowed(&p, io),
                "{} does IO ({io})",
                p.display()
            );
        }
    }
}

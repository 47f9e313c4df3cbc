//! The documentation against the code: every key and every named value the job reader
//! accepts is documented in `docs/job-format.md`, read from the reader's own refusals (an
//! unknown key or value is refused with the list of those it knows), so a table or key
//! that the docs lose or never had fails here; and README's two commands run as written.

use std::process::Command;

/// Where in a job a key or value is probed: the TOML before the probe, and after it.
struct Probe {
    /// What the docs call the table.
    table: &'static str,
    /// The job text with `@` where the unknown key or value goes.
    text: &'static str,
}

/// Every table of a job (and the nested inline tables), with the probe in it.
const TABLES: &[Probe] = &[
    Probe {
        table: "top level",
        text: "@ = 1\n",
    },
    Probe {
        table: "[blank]",
        text: "[blank]\n@ = 1\n",
    },
    Probe {
        table: "[thread]",
        text: "[thread]\n@ = 1\n",
    },
    Probe {
        table: "[thread] pitch",
        text: "[thread]\npitch = { @ = 1 }\n",
    },
    Probe {
        table: "[thread] width",
        text: "[thread]\nwidth = { @ = 1 }\n",
    },
    Probe {
        table: "[[tool]]",
        text: "[[tool]]\n@ = 1\n",
    },
    Probe {
        table: "[[tool]] holder",
        text: "[[tool]]\nholder = { @ = 1 }\n",
    },
    Probe {
        table: "[[pass]]",
        text: "[[pass]]\n@ = 1\n",
    },
    Probe {
        table: "[process]",
        text: "[process]\n@ = 1\n",
    },
    Probe {
        table: "[program]",
        text: "[program]\n@ = 1\n",
    },
    Probe {
        table: "[program] work_offsets",
        text: "[program]\nwork_offsets = { G55 = { @ = 1 } }\n",
    },
    Probe {
        table: "[program] reference_point",
        text: "[program]\nreference_point = { @ = 1 }\n",
    },
    Probe {
        table: "[machine]",
        text: "[machine]\n@ = 1\n",
    },
    Probe {
        table: "[machine] offsets",
        text: "[machine]\noffsets.1 = { @ = 1 }\n",
    },
    Probe {
        table: "[simulation]",
        text: "[simulation]\n@ = 1\n",
    },
    Probe {
        table: "[part]",
        text: "[part]\n@ = 1\n",
    },
];

/// The named values (`kind = "..."` and the like), probed with an unknown name.
const VALUES: &[Probe] = &[
    Probe {
        table: "[[tool]] kind",
        text: "[[tool]]\nid = 1\nkind = \"@\"\n",
    },
    Probe {
        table: "[process] kind",
        text: "[process]\nkind = \"@\"\n",
    },
    Probe {
        table: "[process] schedule",
        text: "[process]\nkind = \"radial\"\ntool = 1\nschedule = \"@\"\n",
    },
    Probe {
        table: "[process] method",
        text: "[process]\nkind = \"radial\"\ntool = 1\nmethod = \"@\"\n",
    },
    Probe {
        table: "[process] infeed",
        text: "[process]\nkind = \"plan\"\ntool = 1\ninfeed = \"@\"\n",
    },
    Probe {
        table: "[thread] form",
        text: "[thread]\nform = \"@\"\n",
    },
];

/// The names the reader lists when it refuses the probe.
fn known(p: &Probe, probe: &str) -> Vec<String> {
    let text = p.text.replace('@', probe);
    let err = match vpcut::Job::from_toml(&text, "probe.toml") {
        Ok(_) => panic!("{}: the probe `{probe}` was accepted", p.table),
        Err(e) => e.to_string(),
    };
    // serde's "unknown field `x`, expected `a`", "... `a` or `b`", "... one of `a`, `b`".
    let Some(at) = err.find(&format!("{probe}`, expected")) else {
        panic!(
            "{}: the refusal of `{probe}` lists no names: {err}",
            p.table
        );
    };
    let line = err[at + probe.len() + 1..].lines().next().unwrap_or("");
    line.split('`')
        .skip(1)
        .step_by(2)
        .map(str::to_string)
        .collect()
}

#[test]
fn every_key_and_named_value_of_a_job_is_documented() {
    let doc = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/job-format.md"),
    )
    .unwrap();
    // The words of the inline code spans: `diameter`, `[blank]`, `{ first = 7.0, .. }`,
    // `kind = "thread-mill"`, `machine.axis`.
    let words: std::collections::BTreeSet<&str> = doc
        .split('`')
        .skip(1)
        .step_by(2)
        .flat_map(|span| span.split(|c: char| !(c.is_alphanumeric() || c == '_' || c == '-')))
        .filter(|w| !w.is_empty())
        .collect();
    let mut missing = Vec::new();
    let mut seen = 0;
    for (probes, probe) in [(TABLES, "zz_not_a_key"), (VALUES, "zz-not-a-name")] {
        for p in probes {
            let names = known(p, probe);
            assert!(!names.is_empty(), "{}: no names", p.table);
            for name in names {
                seen += 1;
                if !words.contains(name.as_str()) {
                    missing.push(format!("{}: `{name}`", p.table));
                }
            }
        }
    }
    // The probes see the whole schema (about 190 keys and names when this was written).
    assert!(seen > 150, "only {seen} keys and names probed");
    assert!(
        missing.is_empty(),
        "docs/job-format.md does not document:\n  {}",
        missing.join("\n  ")
    );
}

#[test]
fn readme_commands_run_as_written() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let readme = std::fs::read_to_string(root.join("README.md")).unwrap();
    let commands: Vec<&str> = readme
        .lines()
        .filter_map(|l| l.trim().strip_prefix("cargo run --release -- "))
        .collect();
    assert_eq!(commands.len(), 2, "README's example commands: {commands:?}");
    let out = std::env::temp_dir().join(format!("vpcut-readme-{}", std::process::id()));
    std::fs::create_dir_all(&out).unwrap();
    for c in commands {
        // Inputs from the repository, outputs in a scratch folder.
        let args: Vec<String> = c
            .split_whitespace()
            .map(|a| {
                if root.join(a).exists() && a.contains('/') {
                    root.join(a).to_string_lossy().into_owned()
                } else if a.contains('.') && !a.starts_with('-') {
                    out.join(a).to_string_lossy().into_owned()
                } else {
                    a.to_string()
                }
            })
            .collect();
        let run = Command::new(env!("CARGO_BIN_EXE_vpcut"))
            .args(&args)
            .output()
            .unwrap();
        let stdout = String::from_utf8_lossy(&run.stdout);
        assert_eq!(
            run.status.code(),
            Some(0),
            "`vpcut {c}`: {}{stdout}",
            String::from_utf8_lossy(&run.stderr)
        );
        // What README says of them: the first fails and writes both files; the plan reads
        // back and passes.
        if c.starts_with("simulate") {
            assert!(stdout.contains("FAIL"), "{stdout}");
            for f in ["report.json", "part.glb"] {
                assert!(out.join(f).exists(), "{f} written");
            }
        } else {
            assert!(
                stdout.contains("read back") && stdout.contains("PASS"),
                "{stdout}"
            );
        }
    }
    std::fs::remove_dir_all(&out).ok();
}

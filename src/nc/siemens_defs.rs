//! Siemens definition files (`Settings::definitions`, the job's `[program] definitions`):
//! what a SINUMERIK holds beside the part programs and a program may rely on (840D sl
//! Programming Manual "Job planning", "Global user data (GUD)" and "Macro technique
//! (DEFINE ... AS)"; the machine maker's cycles in `CMA.DIR`/`CUS.DIR`):
//!
//! - GUD files (`_N_UGUD_DEF`, `MGUD.DEF`, `PGUD.DEF`, ...): `DEF NCK|CHAN type name[dims]
//!   = init` lines define global user data, seen by every program level with their initial
//!   values (`AXIS`/`FRAME` data are skipped; `REDEF ... INIRE` changes no value);
//! - macro files (`_N_SMAC_DEF`, `MMAC.DEF`, ...): `DEFINE NAME AS text`; every block of
//!   every program is loaded with the macro names replaced by their text (`expand`);
//! - cycle files (`NAME.SPF` that start with `PROC NAME(..)`): a cycle callable by that name
//!   wherever the file lies, run as a subprogram.
//!
//! The files are read through the caller's loader, as subprograms are.

use super::lex::Cursor;
use super::program::{load_programs, Program};
use super::{Diagnostic, Dialect, Interp, NcError, Severity};
use std::collections::HashMap;

/// How deep macros may expand within macros (a macro naming itself stops here).
const MAX_MACRO_DEPTH: usize = 8;

impl Interp<'_> {
    /// Read the definition files `names` (macros of every file first, then the data, so
    /// that a GUD's size may be a macro); the warnings of lines that define nothing.
    pub(super) fn load_definitions(
        &mut self,
        names: &[String],
        main: &str,
    ) -> Result<Vec<Diagnostic>, NcError> {
        if names.is_empty() {
            return Ok(Vec::new());
        }
        if self.cfg.dialect != Dialect::Siemens802d {
            return Err(NcError::from_diagnostics(vec![Diagnostic {
                severity: Severity::Error,
                file: main.to_string(),
                line: 1,
                col: 0,
                message: "definition files (GUD, macros, cycles) are Siemens data".into(),
                hint: Some(
                    "[program] definitions is for the siemens-802d and siemens-840d dialects"
                        .into(),
                ),
                snippet: String::new(),
                stack: Vec::new(),
            }]));
        }
        let mut files = Vec::new();
        for name in names {
            let src = (self.progs.loader)(name).ok_or_else(|| NcError {
                file: name.clone(),
                line: 0,
                col: 0,
                message: format!(
                    "definition file `{name}` not found (the job's [program] definitions)"
                ),
                snippet: String::new(),
                stack: Vec::new(),
                hint: Some("definition files are named relative to the program's folder".into()),
                others: Vec::new(),
            })?;
            let prog = load_programs(&src, self.cfg.dialect, false)
                .into_iter()
                .next()
                .expect("one program");
            files.push(prog);
        }
        // Macros, and which files are cycles.
        let mut cycles = Vec::new();
        for (k, prog) in files.iter().enumerate() {
            let mut first = true;
            for (_, _, text) in &prog.blocks {
                let t = without_n(text);
                if t.is_empty() {
                    continue;
                }
                if first && t.starts_with("PROC ") {
                    let name: String = t[5..]
                        .trim_start()
                        .chars()
                        .take_while(|ch| ch.is_ascii_alphanumeric() || *ch == '_')
                        .collect();
                    cycles.push((k, name));
                }
                first = false;
                if let Some(rest) = t.strip_prefix("DEFINE ") {
                    if let Some((name, body)) = rest.split_once(" AS ") {
                        self.vars
                            .s840
                            .macros
                            .insert(name.trim().to_string(), body.trim().to_string());
                    }
                }
            }
        }
        let mut warnings = Vec::new();
        let mut files: Vec<Option<Program>> = files.into_iter().map(Some).collect();
        for (k, name) in cycles {
            let mut prog = files[k].take().expect("each file once");
            expand_program(&mut prog, &self.vars.s840.macros);
            let prog = std::rc::Rc::new(prog);
            self.register(prog.clone());
            self.progs.by_name.insert(name, prog);
        }
        // The data of the GUD files.
        for prog in files.into_iter().flatten() {
            for (line, orig, text) in &prog.blocks {
                let t = expand(without_n(text), &self.vars.s840.macros);
                let mut c = Cursor::new(&t, self.cfg.dialect);
                let word = c.name_with_digits();
                let result = match word.as_str() {
                    "DEF" => self.def_global(&mut c),
                    // Nothing to define: initial values reset at power-on, the file's
                    // header and end, macros (read above).
                    "" | "REDEF" | "DEFINE" | "M30" | "M17" | "M02" | "M2" | "RET" => Ok(()),
                    _ => {
                        warnings.push(Diagnostic {
                            severity: Severity::Warning,
                            file: prog.name.clone(),
                            line: *line,
                            col: 0,
                            message: "a line of a definition file that is neither DEF nor DEFINE: skipped".into(),
                            hint: Some("a GUD file holds DEF lines, a macro file DEFINE lines; a cycle file starts with PROC".into()),
                            snippet: orig.clone(),
                            stack: Vec::new(),
                        });
                        Ok(())
                    }
                };
                if let Err((col, message)) = result {
                    return Err(NcError {
                        file: prog.name.clone(),
                        line: *line,
                        col,
                        message,
                        snippet: orig.clone(),
                        stack: Vec::new(),
                        hint: Some("a definition file of [program] definitions".into()),
                        others: warnings,
                    });
                }
            }
        }
        Ok(warnings)
    }
}

/// A block's text after its block number.
fn without_n(text: &str) -> &str {
    let t = text.trim_start();
    match t.strip_prefix('N') {
        Some(rest) if rest.starts_with(|c: char| c.is_ascii_digit()) => rest
            .trim_start_matches(|c: char| c.is_ascii_digit())
            .trim_start(),
        _ => t,
    }
}

/// `text` with every name that is a macro replaced by the macro's text (names inside
/// strings are left alone; a macro's text is expanded again, `MAX_MACRO_DEPTH` deep).
pub(super) fn expand(text: &str, macros: &HashMap<String, String>) -> String {
    if macros.is_empty() {
        return text.to_string();
    }
    expand_at(text, macros, 0)
}

fn expand_at(text: &str, macros: &HashMap<String, String>, depth: usize) -> String {
    let b = text.as_bytes();
    let mut out = String::with_capacity(text.len());
    let mut i = 0;
    while i < b.len() {
        let ch = b[i];
        if ch == b'"' {
            let end = text[i + 1..].find('"').map_or(b.len(), |k| i + 2 + k);
            out.push_str(&text[i..end]);
            i = end;
        } else if ch.is_ascii_alphabetic() || ch == b'_' {
            let st = i;
            while i < b.len() && (b[i].is_ascii_alphanumeric() || b[i] == b'_') {
                i += 1;
            }
            let name = &text[st..i];
            match macros.get(name) {
                Some(body) if depth < MAX_MACRO_DEPTH => {
                    out.push_str(&expand_at(body, macros, depth + 1));
                }
                _ => out.push_str(name),
            }
        } else {
            let len = text[i..].chars().next().map_or(1, char::len_utf8);
            out.push_str(&text[i..i + len]);
            i += len;
        }
    }
    out
}

/// `prog`'s blocks with the macros expanded.
pub(super) fn expand_program(prog: &mut Program, macros: &HashMap<String, String>) {
    if macros.is_empty() {
        return;
    }
    for block in &mut prog.blocks {
        block.2 = expand(&block.2, macros);
    }
}

#[cfg(test)]
mod tests {
    //! Definition files against values worked by hand, and the 802D read as the 840D
    //! where the two agree (issue 27).
    use super::super::*;
    use super::expand;

    /// Run `text` (T.MPF) with `files` (name, text) beside it and `defs` named.
    fn run_defs(
        text: &str,
        dialect: Dialect,
        files: &[(&str, &str)],
        defs: &[&str],
    ) -> Result<Toolpath, NcError> {
        let src = Source {
            name: "T.MPF".into(),
            text: text.into(),
        };
        let mut opts = Options::default();
        opts.settings.definitions = defs.iter().map(|d| d.to_string()).collect();
        let files: Vec<(String, String)> = files
            .iter()
            .map(|(n, t)| (n.to_string(), t.to_string()))
            .collect();
        let load = move |n: &str| {
            files.iter().find(|f| f.0 == n).map(|f| Source {
                name: f.0.clone(),
                text: f.1.clone(),
            })
        };
        interpret_with(&src, dialect, &load, &opts)
    }

    fn xs(t: &Toolpath) -> Vec<f64> {
        t.moves.iter().map(|m| m.x_dia).collect()
    }

    const GUD: &str = "%_N_UGUD_DEF\n;$PATH=/_N_DEF_DIR\nN10 DEF NCK REAL TEST=2\nN11 REDEF TEST INIRE\nDEF CHAN INT NN[3]=(1,2,3), KK\nDef Chan String[8] WHEEL[2]=REP(\"K;1\")\nDEF CHAN AXIS OSC=(Z)\nDEF NCK REAL BIG[2]=REP(NOVAL)\nM30\n";
    const MAC: &str = "DEFINE DEPTH AS 1.5\nDEFINE NOVAL AS 1EX300\nDEFINE HOME AS G0 X100 Z50\n";
    const CYC: &str =
        "PROC MYCYC(REAL DIA, STRING[8] NAME, INT NUM) SAVE\nG1 X=DIA+NUM F0.1\nM17\n";

    #[test]
    fn gud_macros_and_cycles_come_from_the_definition_files() {
        let prog = "G0 X=NN[2]*10 Z2\nG1 X=TEST*10+DEPTH F0.2\nMYCYC(40, \"ABC\", 2)\nKK=7\nG0 X=KK\nHOME\nM30\n";
        let files = [("UGUD.DEF", GUD), ("SMAC.DEF", MAC), ("CYC/MYCYC.SPF", CYC)];
        let defs = ["UGUD.DEF", "SMAC.DEF", "CYC/MYCYC.SPF"];
        for dialect in [Dialect::Siemens840d, Dialect::Siemens802d] {
            let t = run_defs(prog, dialect, &files, &defs).unwrap();
            // NN[2] = 3 -> X30; TEST*10 + DEPTH = 21.5; the cycle X = 40 + 2; KK; HOME.
            assert_eq!(xs(&t), vec![30.0, 21.5, 42.0, 7.0, 100.0], "{dialect:?}");
            assert_eq!(t.moves.last().unwrap().z, 50.0);
            assert!(t.warnings.is_empty(), "{dialect:?}: {:?}", t.warnings);
        }
        // Without the files the GUD is a warning on both and the cycle is skipped.
        let prog = "TEST=1\nG0 X=TEST*10 Z0\n_APPROACH(\"KRUG1\",1,0)\nM30\n";
        for dialect in [Dialect::Siemens840d, Dialect::Siemens802d] {
            let t = run_defs(prog, dialect, &[], &[]).unwrap();
            assert_eq!(xs(&t), vec![10.0], "{dialect:?}");
            let w: Vec<&str> = t.warnings.iter().map(|d| d.message.as_str()).collect();
            assert_eq!(w.len(), 2, "{dialect:?}: {w:?}");
            assert!(w[0].contains("`TEST` is not defined"), "{w:?}");
            assert!(w[1].contains("`_APPROACH` not found"), "{w:?}");
        }
    }

    #[test]
    fn definition_files_that_are_missing_or_wrong_are_errors() {
        let e = run_defs("M30\n", Dialect::Siemens840d, &[], &["NONE.DEF"]).unwrap_err();
        assert!(e.message.contains("`NONE.DEF` not found"), "{e}");
        let bad = [("G.DEF", "DEF CHAN REAL A[0]\n")];
        let e = run_defs("M30\n", Dialect::Siemens840d, &bad, &["G.DEF"]).unwrap_err();
        assert_eq!((e.file.as_str(), e.line), ("G.DEF", 1), "{e}");
        let e = run_defs("M30\n", Dialect::Fanuc, &bad, &["G.DEF"]).unwrap_err();
        assert!(e.message.contains("Siemens data"), "{e}");
        // A line that defines nothing is a warning naming its file and line.
        let odd = [("G.DEF", "DEF CHAN REAL AA\nG0 X10\n")];
        let t = run_defs("M30\n", Dialect::Siemens840d, &odd, &["G.DEF"]).unwrap();
        assert_eq!(
            (t.warnings[0].file.as_str(), t.warnings[0].line),
            ("G.DEF", 2)
        );
    }

    #[test]
    fn macros_expand_names_only_outside_strings() {
        let m: HashMap<String, String> = [("AB", "12"), ("LOOP", "LOOP")]
            .iter()
            .map(|(a, b)| (a.to_string(), b.to_string()))
            .collect();
        assert_eq!(expand("X=AB+ABC MSG(\"AB\")", &m), "X=12+ABC MSG(\"AB\")");
        // A macro naming itself stops after MAX_MACRO_DEPTH levels, unchanged.
        assert_eq!(expand("LOOP", &m), "LOOP");
    }

    #[test]
    fn the_802d_reads_headers_spindles_diameter_modes_and_g53() {
        let prog = "%_N_T_MPF\n;$PATH=/_N_MPF_DIR\nM3=3 S3=1500\nS1=800 M1=3\nG0 X40 Z5\nDIAMOF\nG0 X10\nDIAMON\nG53 G0 X0\nMSG(\"A;B\")\nM30\n";
        let t = run_defs(prog, Dialect::Siemens802d, &[], &[]).unwrap();
        // X40 (diameter), X10 a radius (20 diameter), G53 X0 in machine coordinates.
        assert_eq!(xs(&t), vec![40.0, 20.0, 0.0]);
        assert_eq!(t.moves[0].speed.rpm, Some(800.0));
        let w: Vec<&str> = t.warnings.iter().map(|d| d.message.as_str()).collect();
        assert_eq!(w.len(), 2, "{w:?}");
        assert!(
            w.iter()
                .all(|m| m.contains("spindle 3 is not the work spindle")),
            "{w:?}"
        );
    }
}

//! The designation parser: spellings people write (accepted, with what they mean), spellings
//! refused (each message naming what was expected), and random junk that must never panic.

use super::*;
use crate::model::Rng;

/// An accepted spelling: text, normalised designation, standard, major (mm), pitch (mm),
/// starts, left hand, class text ("" for none), the side it implies.
struct Accepted(
    &'static str,
    &'static str,
    Standard,
    f64,
    f64,
    u32,
    bool,
    Option<Side>,
);

#[test]
fn accepted_spellings() {
    use Side::{External as E, Internal as I};
    use Standard::*;
    let un = |s| Unified(s);
    let inch = 25.4;
    #[rustfmt::skip]
    let rows = [
        // ISO 965-1 §7 designations.
        Accepted("M30x2-6g", "M30x2-6g", Metric, 30.0, 2.0, 1, false, Some(E)),
        Accepted("m30 x 2 - 6g", "M30x2-6g", Metric, 30.0, 2.0, 1, false, Some(E)),
        Accepted("M30×2-6g", "M30x2-6g", Metric, 30.0, 2.0, 1, false, Some(E)),
        Accepted("M 30 X 2 -6g", "M30x2-6g", Metric, 30.0, 2.0, 1, false, Some(E)),
        // ISO 261 coarse pitch when none is written.
        Accepted("M20-6H", "M20-6H", Metric, 20.0, 2.5, 1, false, Some(I)),
        Accepted("M20", "M20", Metric, 20.0, 2.5, 1, false, None),
        Accepted("M1,6", "M1.6", Metric, 1.6, 0.35, 1, false, None),
        Accepted("M10x1,25-6H", "M10x1.25-6H", Metric, 10.0, 1.25, 1, false, Some(I)),
        Accepted("M12x1.25-4h6h", "M12x1.25-4h6h", Metric, 12.0, 1.25, 1, false, Some(E)),
        Accepted("M10x1-6H/6g", "M10x1-6H/6g", Metric, 10.0, 1.0, 1, false, None),
        Accepted("M20x2-5g6g-S-LH", "M20x2-5g6g-S-LH", Metric, 20.0, 2.0, 1, true, Some(E)),
        Accepted("M20x2 LH-6g", "M20x2-6g-LH", Metric, 20.0, 2.0, 1, true, Some(E)),
        Accepted("M20x2-6g-40", "M20x2-6g-40", Metric, 20.0, 2.0, 1, false, Some(E)),
        Accepted("M16xPh3P1.5-6g", "M16xPh3P1.5-6g", Metric, 16.0, 1.5, 2, false, Some(E)),
        Accepted("M30X2-6G", "M30x2-6G", Metric, 30.0, 2.0, 1, false, None),
        Accepted("M30X2-6E", "M30x2-6E", Metric, 30.0, 2.0, 1, false, Some(E)),
        // ISO 2903 §12.
        Accepted("Tr40x7-7e", "Tr40x7-7e", Trapezoidal, 40.0, 7.0, 1, false, Some(E)),
        Accepted("TR 40 x 7 - 7H", "Tr40x7-7H", Trapezoidal, 40.0, 7.0, 1, false, Some(I)),
        Accepted("Tr40x14(P7)-8e", "Tr40x14(P7)-8e", Trapezoidal, 40.0, 7.0, 2, false, Some(E)),
        Accepted("Tr 40x14 (P7) LH-8e", "Tr40x14(P7)-8e-LH", Trapezoidal, 40.0, 7.0, 2, true, Some(E)),
        Accepted("Tr100x12", "Tr100x12", Trapezoidal, 100.0, 12.0, 1, false, None),
        // ASME B1.1 §7.
        Accepted("1/2-13 UNC-2B", "1/2-13 UNC-2B", un(Series::Coarse), 0.5 * inch, inch / 13.0, 1, false, Some(I)),
        Accepted("1/2-13UNC-2B", "1/2-13 UNC-2B", un(Series::Coarse), 0.5 * inch, inch / 13.0, 1, false, Some(I)),
        Accepted("3/4-16 UNF-3A", "3/4-16 UNF-3A", un(Series::Fine), 0.75 * inch, inch / 16.0, 1, false, Some(E)),
        Accepted("#10-32 UNF-2A", "#10-32 UNF-2A", un(Series::Fine), 0.19 * inch, inch / 32.0, 1, false, Some(E)),
        Accepted("1/4-20 unc-2a", "1/4-20 UNC-2A", un(Series::Coarse), 0.25 * inch, inch / 20.0, 1, false, Some(E)),
        Accepted("1-8 UN-2A", "1-8 UN-2A", un(Series::Constant), inch, inch / 8.0, 1, false, Some(E)),
        Accepted("1/2-28 UNEF-2B", "1/2-28 UNEF-2B", un(Series::ExtraFine), 0.5 * inch, inch / 28.0, 1, false, Some(I)),
        Accepted("19/64-36 UNS-2A", "19/64-36 UNS-2A", un(Series::Special), 19.0 / 64.0 * inch, inch / 36.0, 1, false, Some(E)),
        Accepted("1 1/4-7 UNC-2A", "1 1/4-7 UNC-2A", un(Series::Coarse), 1.25 * inch, inch / 7.0, 1, false, Some(E)),
        Accepted("1-1/4-7 UNC-2A", "1 1/4-7 UNC-2A", un(Series::Coarse), 1.25 * inch, inch / 7.0, 1, false, Some(E)),
        Accepted("0.250-20 UNC-2A", "0.25-20 UNC-2A", un(Series::Coarse), 0.25 * inch, inch / 20.0, 1, false, Some(E)),
        Accepted("1/2-13 UNC-2A-LH", "1/2-13 UNC-2A-LH", un(Series::Coarse), 0.5 * inch, inch / 13.0, 1, true, Some(E)),
        Accepted("1/2-13 UNC", "1/2-13 UNC", un(Series::Coarse), 0.5 * inch, inch / 13.0, 1, false, None),
        // ASME B1.5, B1.20.1.
        Accepted("1-8 ACME-2G", "1-8 ACME-2G", Acme, inch, inch / 8.0, 1, false, None),
        Accepted("1/2-14 NPT", "1/2-14 NPT", Npt, 0.0, inch / 14.0, 1, false, None),
        Accepted("1/2 NPT", "1/2-14 NPT", Npt, 0.0, inch / 14.0, 1, false, None),
        // ISO 228-1, ISO 7-1.
        Accepted("G1/2 A", "G1/2 A", PipeParallel, 20.955, inch / 14.0, 1, false, Some(E)),
        Accepted("G 1/2 b", "G1/2 B", PipeParallel, 20.955, inch / 14.0, 1, false, Some(E)),
        Accepted("G1/2", "G1/2", PipeParallel, 20.955, inch / 14.0, 1, false, Some(I)),
        Accepted("G1 1/2 A", "G1 1/2 A", PipeParallel, 47.803, inch / 11.0, 1, false, Some(E)),
        Accepted("R1/2", "R1/2", PipeTaper { internal: false }, 20.955, inch / 14.0, 1, false, Some(E)),
        Accepted("Rc1/2", "Rc1/2", PipeTaper { internal: true }, 20.955, inch / 14.0, 1, false, Some(I)),
        Accepted("RP 3/4", "Rp3/4", PipeParallelInternal, 26.441, inch / 14.0, 1, false, Some(I)),
    ];
    for Accepted(text, norm, standard, major, pitch, starts, lh, side) in rows {
        let d = parse(text).unwrap_or_else(|e| panic!("{text}: {e}"));
        assert_eq!(d.text, norm, "{text}");
        assert_eq!(d.standard, standard, "{text}");
        if standard != Npt {
            assert!((d.major - major).abs() < 1e-9, "{text}: major {}", d.major);
        }
        assert!((d.pitch - pitch).abs() < 1e-9, "{text}: pitch {}", d.pitch);
        assert_eq!((d.starts, d.left_hand), (starts, lh), "{text}");
        assert_eq!(d.implied_side(), side, "{text}");
        // The normalised text reads back to the same thread.
        let again = parse(&d.text).unwrap_or_else(|e| panic!("{}: {e}", d.text));
        assert_eq!(
            (again.text.as_str(), again.major, again.pitch, again.starts),
            (d.text.as_str(), d.major, d.pitch, d.starts),
            "{text}"
        );
    }
}

#[test]
fn refused_spellings_say_what_was_expected() {
    #[rustfmt::skip]
    let rows = [
        ("", "expected a thread designation"),
        ("   ", "expected a thread designation"),
        ("X20", "expected a designation: M (ISO metric)"),
        ("M", "expected the nominal diameter (mm) after M at character 2, found the end"),
        ("Mx2", "expected the nominal diameter (mm) after M at character 2, found `x`"),
        ("M20x", "expected the pitch (mm) after x at character 5"),
        ("M20x0", "greater than 0"),
        ("M23", "M23 has no coarse pitch in ISO 261"),
        ("M20x15", "a pitch less than half the diameter"),
        ("M20x2-6k", "position `k` is not in vpcut: expected e, f, g or h"),
        ("M20x2-6gH", "expected an ISO 965 tolerance class such as 6g"),
        ("M20x2-6g6H", "both positions in lower case (external) or both in upper case"),
        ("M20x2-6g/6H", "a fit written internal class first"),
        ("M20x2-6g-Q", "expected a tolerance class (6g, 6H), a length of engagement"),
        ("M20x2-6g-LH-LH", "expected LH once"),
        ("M20x2--6g", "a class, a length of engagement or LH after `-`"),
        ("M16xPh3P2", "the lead to be 1 to 64 times the pitch"),
        ("M16xPh3", "P and the pitch after the lead"),
        ("Tr40", "x and the pitch (Tr40x7)"),
        ("Tr40x14(7)", "P and the pitch: Tr40x14(P7)"),
        ("Tr40x14(P7", "`)` after the pitch"),
        ("Tr40x14(P5)", "the lead to be 1 to 64 times the pitch"),
        ("Tr40x7-6g", "expected an ISO 2903 class: 7e, 8e, 8c, 9c"),
        ("1/2-14 UNC-2B", "1/2 UNC has 13 threads per inch (ASME B1.1 Table 1), not 14"),
        ("11/16-20 UNF", "11/16 is not a size of the UNF series"),
        ("1-10 UN-2A", "not a constant-pitch UN series"),
        ("1/2-13 UNX-2B", "expected the series: UNC, UNF, UNEF, UN, UNS, ACME or NPT"),
        ("1/2 UNC-2B", "`-` and the threads per inch before the series"),
        ("1/2-13 UNC-2C", "expected an ASME B1.1 class: 1A, 2A, 3A"),
        ("1/2-13 UNC-4A", "expected an ASME B1.1 class"),
        ("#14-24 UNC", "expected a number size #0 to #12"),
        ("1/0-13 UNC", "a non-zero numerator and denominator"),
        ("1 5/4-7 UNC", "a proper fraction after the whole inches"),
        ("1/2-13", "expected the series"),
        ("1/2-18 NPT", "1/2 NPT has 14 threads per inch (ASME B1.20.1), not 18"),
        ("5/8-14 NPT", "5/8 is not an NPT size (ASME B1.20.1: 1/16, 1/8"),
        ("1/2-14 NPT-2A", "no class after NPT"),
        ("G5/16", "G5/16 is not an ISO 228-1 size"),
        ("G1/2 C", "the class A or B (ISO 228-1)"),
        ("R5/8", "R5/8 is not an ISO 7-1 size"),
        ("Rc", "a pipe size after R, Rc or Rp"),
        ("M20x2-S-6g", "in that order"),
        ("M99999999999999x2", "at most 12 digits"),
    ];
    for (text, want) in rows {
        let e = parse(text).expect_err(text).message;
        assert!(e.contains(want), "{text}: `{e}` does not say `{want}`");
        assert!(!e.contains("Some(") && !e.contains("None"), "{text}: {e}");
    }
}

#[test]
fn junk_never_panics() {
    // Random strings over the designations' alphabet (and a few strangers), and random
    // mutations of valid designations: parse and, where it parses, every class query.
    let alphabet: Vec<char> = "Mm TtRrGgUuNnCcFfEeSsAaPpHhLlxX×#-/.,()0123456789 éΩ\t"
        .chars()
        .collect();
    let seeds = [
        "M30x2-6g",
        "1/2-13 UNC-2B",
        "Tr40x14(P7)-8e",
        "G1/2 A",
        "1/2-14 NPT",
        "M10x1-6H/6g",
        "M16xPh3P1.5-6g",
        "1-8 ACME-2G",
        "Rc1/2",
        "M20x2-5g6g-S-LH",
        "#10-32 UNF-2A",
    ];
    let mut rng = Rng(0x5eed_7e57_0dd5_u64);
    let pick = |rng: &mut Rng, n: usize| ((rng.next() * n as f64) as usize).min(n - 1);
    for i in 0..30_000 {
        let text: String = if i % 2 == 0 {
            let n = pick(&mut rng, 24);
            (0..n)
                .map(|_| alphabet[pick(&mut rng, alphabet.len())])
                .collect()
        } else {
            let mut s: Vec<char> = seeds[pick(&mut rng, seeds.len())].chars().collect();
            for _ in 0..1 + pick(&mut rng, 3) {
                let at = pick(&mut rng, s.len() + 1);
                match pick(&mut rng, 3) {
                    0 if at < s.len() => {
                        s.remove(at);
                    }
                    1 => s.insert(at, alphabet[pick(&mut rng, alphabet.len())]),
                    _ if at < s.len() => s[at] = alphabet[pick(&mut rng, alphabet.len())],
                    _ => {}
                }
            }
            s.into_iter().collect()
        };
        if let Ok(d) = parse(&text) {
            assert!(
                d.major.is_finite() && d.pitch > 0.0 && d.starts >= 1,
                "{text}"
            );
            for side in [None, Some(Side::External), Some(Side::Internal)] {
                if let Ok(Some(c)) = d.class(side) {
                    assert!(
                        c.pitch_diameter.min <= c.pitch_diameter.max,
                        "{text}: {:?}",
                        c.pitch_diameter
                    );
                }
            }
        }
    }
}

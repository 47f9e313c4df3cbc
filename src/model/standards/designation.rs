//! The designation parser: a drawing's thread designation, as people write it, into a
//! [`Designation`].
//!
//! Accepted (letters in any case unless said, spaces anywhere between the parts, `x`, `X`
//! or `×` between diameter and pitch, `,` as a decimal point in metric sizes):
//!
//! - ISO metric (ISO 965-1 §7): `M20`, `M30x2`, `M16xPh3P1.5` (lead 3, pitch 1.5), then
//!   `-6g`, `-4h6h` (pitch diameter first, then crest), `-6H/6g` (a fit), `-S`/`-N`/`-L`
//!   or `-40` (length of engagement, mm), `-LH`. A pitch left out is ISO 261's coarse one.
//! - ISO trapezoidal (ISO 2903 §12): `Tr40x7`, `Tr40x14(P7)` (lead 14, pitch 7: 2
//!   starts), `LH` after the size or at the end, then `-7e`, `-7H/7e`.
//! - Unified (ASME B1.1 §7): `1/2-13 UNC-2B`, `#10-32 UNF-2A`, `1 1/4-7 UNC` (or
//!   `1-1/4-7`), `0.250-20 UNC`, series UNC UNF UNEF UN UNS, class 1A 2A 3A 1B 2B 3B, `-LH`.
//! - Acme (ASME B1.5): `1-8 ACME-2G`.
//! - NPT (ASME B1.20.1): `1/2-14 NPT` or `1/2 NPT`.
//! - ISO 228-1: `G1/2` (internal), `G1/2 A`, `G1/2 B` (external); ISO 7-1: `R1/2`,
//!   `Rc1/2`, `Rp1/2`.
//!
//! Case: ISO 965 tells the side by a position letter's case (lower external, upper
//! internal). A designation written all in capitals, the `x` too (`M30X2-6G`), cannot say
//! it for G and H: vpcut then takes the side the job gives, and otherwise refuses (E and F
//! are external in any case: ISO 965 has no internal E or F). `M20-6H` has no letter ISO
//! writes in lower case: it is ISO's internal 6H. Tr's C and E are external and H internal
//! in any case.

use super::iso965::{self, MetricClass};
use super::unified::{self, Series, UnifiedClass};
use super::{pipe, ClassSpec, Designation, Engagement, Standard, StandardError};

/// The longest designation read (characters).
const MAX_LEN: usize = 120;

/// A number for a designation: no trailing zeros (`2.5`, `30`, `1.25`).
pub(super) fn fmt_num(v: f64) -> String {
    let s = format!("{:.6}", v);
    let s = s.trim_end_matches('0').trim_end_matches('.');
    s.to_string()
}

/// A cursor over the designation's characters; errors say the 1-based character.
struct Cursor<'a> {
    text: &'a str,
    chars: Vec<char>,
    i: usize,
}

impl<'a> Cursor<'a> {
    fn new(text: &'a str) -> Cursor<'a> {
        Cursor {
            text,
            chars: text.chars().collect(),
            i: 0,
        }
    }

    fn peek(&self) -> Option<char> {
        self.chars.get(self.i).copied()
    }

    fn peek_at(&self, k: usize) -> Option<char> {
        self.chars.get(self.i + k).copied()
    }

    fn at_end(&self) -> bool {
        self.i >= self.chars.len()
    }

    fn skip_ws(&mut self) {
        while self.peek().is_some_and(char::is_whitespace) {
            self.i += 1;
        }
    }

    /// Whether the next characters are `word` (ASCII, any case); consumes them if so.
    fn eat_word(&mut self, word: &str) -> bool {
        let n = word.chars().count();
        let matches = word
            .chars()
            .enumerate()
            .all(|(k, w)| self.peek_at(k).is_some_and(|c| c.eq_ignore_ascii_case(&w)));
        if matches {
            self.i += n;
        }
        matches
    }

    fn eat(&mut self, c: char) -> bool {
        if self.peek() == Some(c) {
            self.i += 1;
            true
        } else {
            false
        }
    }

    /// An error at the cursor: what was expected, and what was found.
    fn expected(&self, what: &str) -> StandardError {
        let found = match self.peek() {
            Some(c) => format!("`{c}`"),
            None => "the end".to_string(),
        };
        StandardError::new(format!(
            "`{}`: expected {what} at character {}, found {found}",
            self.text,
            self.i + 1
        ))
    }

    /// Digits with an optional decimal point (`.` or, for metric sizes, `,`).
    fn number(&mut self, what: &str, comma: bool) -> Result<f64, StandardError> {
        let start = self.i;
        let mut s = String::new();
        let mut point = false;
        while let Some(c) = self.peek() {
            if c.is_ascii_digit() {
                s.push(c);
            } else if (c == '.' || (comma && c == ',')) && !point {
                // A point must be followed by a digit to belong to the number.
                if !self.peek_at(1).is_some_and(|d| d.is_ascii_digit()) {
                    break;
                }
                point = true;
                s.push('.');
            } else {
                break;
            }
            self.i += 1;
        }
        if s.is_empty() || s == "." {
            self.i = start;
            return Err(self.expected(what));
        }
        if s.len() > 12 {
            self.i = start;
            return Err(self.expected(&format!("{what} (at most 12 digits)")));
        }
        let v: f64 = s.parse().map_err(|_| {
            let mut c = Cursor::new(self.text);
            c.i = start;
            c.expected(what)
        })?;
        if v <= 0.0 || !v.is_finite() {
            self.i = start;
            return Err(self.expected(&format!("{what} greater than 0")));
        }
        Ok(v)
    }

    fn integer(&mut self, what: &str) -> Result<u32, StandardError> {
        let start = self.i;
        let mut n: u64 = 0;
        while let Some(d) = self.peek().and_then(|c| c.to_digit(10)) {
            n = n * 10 + d as u64;
            if n > 100_000 {
                self.i = start;
                return Err(self.expected(&format!("{what} (a small whole number)")));
            }
            self.i += 1;
        }
        if self.i == start {
            return Err(self.expected(what));
        }
        Ok(n as u32)
    }
}

/// Reads a thread designation.
pub fn parse(text: &str) -> Result<Designation, StandardError> {
    let t = text.trim();
    if t.is_empty() {
        return Err(StandardError::new(
            "expected a thread designation such as M30x2-6g, 1/2-13 UNC-2B, Tr40x7-7e, G1/2 A or 1/2-14 NPT",
        ));
    }
    if t.chars().count() > MAX_LEN {
        return Err(StandardError::new(format!(
            "expected a thread designation of at most {MAX_LEN} characters"
        )));
    }
    // Capitals mean nothing only where a letter ISO writes in lower case is in capitals too
    // (the `x` between diameter and pitch, Ph's h): `M20-6H` is ISO's internal 6H.
    let upper = t.to_uppercase();
    let all_caps =
        !t.chars().any(|c| c.is_lowercase()) && (upper.contains('X') || upper.contains("PH"));
    let mut c = Cursor::new(t);
    let first = c.peek().map(|ch| ch.to_ascii_uppercase());
    let second = c.peek_at(1).map(|ch| ch.to_ascii_uppercase());
    let mut d = match (first, second) {
        (Some('T'), Some('R')) => trapezoidal(&mut c)?,
        (Some('M'), _) => metric(&mut c)?,
        (Some('G'), _) => pipe_g(&mut c)?,
        (Some('R'), _) => pipe_r(&mut c)?,
        (Some(ch), _) if ch.is_ascii_digit() || ch == '#' || ch == '.' => inch(&mut c)?,
        _ => {
            return Err(c.expected(
                "a designation: M (ISO metric), Tr (trapezoidal), G or R/Rc/Rp (pipe), or an inch size (1/2-13 UNC, 1-8 ACME, 1/2-14 NPT)",
            ))
        }
    };
    d.all_caps = all_caps;
    Ok(d)
}

/// The parts after the size and pitch: class, length of engagement, `LH`, separated by `-`
/// or spaces. `classes` reads a class token.
struct Tail {
    class: Option<(String, usize)>,
    group: Option<Engagement>,
    left_hand: bool,
}

fn tail(c: &mut Cursor, groups: bool, class_what: &str) -> Result<Tail, StandardError> {
    let mut out = Tail {
        class: None,
        group: None,
        left_hand: false,
    };
    loop {
        c.skip_ws();
        if c.at_end() {
            return Ok(out);
        }
        if c.eat('-') {
            c.skip_ws();
        }
        let start = c.i;
        let mut token = String::new();
        while let Some(ch) = c.peek() {
            if ch == '-' || ch.is_whitespace() {
                break;
            }
            token.push(ch);
            c.i += 1;
        }
        if token.is_empty() {
            c.i = start;
            return Err(c.expected("a class, a length of engagement or LH after `-`"));
        }
        let upper = token.to_ascii_uppercase();
        let at = |c: &mut Cursor| c.i = start;
        if upper == "LH" {
            if out.left_hand {
                at(c);
                return Err(c.expected("LH once"));
            }
            out.left_hand = true;
        } else if groups && out.group.is_none() && matches!(upper.as_str(), "S" | "N" | "L") {
            out.group = Some(match upper.as_str() {
                "S" => Engagement::Short,
                "N" => Engagement::Normal,
                _ => Engagement::Long,
            });
        } else if groups
            && out.class.is_some()
            && out.group.is_none()
            && token.chars().all(|ch| ch.is_ascii_digit() || ch == '.')
        {
            let mut n = Cursor::new(c.text);
            n.i = start;
            out.group = Some(Engagement::Length(
                n.number("a length of engagement (mm)", false)?,
            ));
            if n.i != c.i {
                return Err(n.expected("a length of engagement (mm)"));
            }
        } else if out.class.is_none()
            && out.group.is_none()
            && token.starts_with(|ch: char| ch.is_ascii_digit())
        {
            out.class = Some((token, start));
        } else {
            at(c);
            let what = if groups {
                format!("{class_what}, a length of engagement (S, N, L or mm) or LH, in that order")
            } else {
                format!("{class_what} or LH")
            };
            return Err(c.expected(&what));
        }
    }
}

/// An error about a token that starts at character `at`.
fn token_error(text: &str, at: usize, what: &str) -> StandardError {
    let mut c = Cursor::new(text);
    c.i = at;
    c.expected(what)
}

/// One grade-and-position pair (`6g`): grade digit and letter.
fn grade_letter(s: &str) -> Option<(u8, char)> {
    let mut it = s.chars();
    let g = it.next()?.to_digit(10)? as u8;
    let l = it.next()?;
    (l.is_ascii_alphabetic()).then_some((g, l))
}

/// ISO 965 class text (`6g`, `4h6h`, `6H`) into its pitch and crest parts.
pub(super) fn metric_class(s: &str) -> Result<MetricClass, StandardError> {
    let bad = || {
        StandardError::new(format!(
            "expected an ISO 965 tolerance class such as 6g, 4h6h, 6H or 5H6H (grade then position, pitch diameter first), got `{s}`"
        ))
    };
    let chars: Vec<char> = s.chars().collect();
    let (pitch, crest) = match chars.len() {
        2 => {
            let p = grade_letter(s).ok_or_else(bad)?;
            (p, p)
        }
        4 => {
            let a: String = chars[..2].iter().collect();
            let b: String = chars[2..].iter().collect();
            (
                grade_letter(&a).ok_or_else(bad)?,
                grade_letter(&b).ok_or_else(bad)?,
            )
        }
        _ => return Err(bad()),
    };
    let known = |l: char| "efghEFGH".contains(l);
    for (_, l) in [pitch, crest] {
        if !known(l) {
            return Err(StandardError::new(format!(
                "`{s}`: ISO 965 position `{l}` is not in vpcut: expected e, f, g or h (external, lower case), G or H (internal, upper case); ISO 965-1:2013's a, b, c and d have no public deviations"
            )));
        }
    }
    if pitch.1.is_ascii_uppercase() != crest.1.is_ascii_uppercase() {
        return Err(StandardError::new(format!(
            "`{s}`: expected both positions in lower case (external) or both in upper case (internal)"
        )));
    }
    Ok(MetricClass { pitch, crest })
}

/// ASME B1.1 class text (`2A`).
pub(super) fn unified_class(s: &str) -> Result<UnifiedClass, StandardError> {
    let mut it = s.chars();
    let ok = match (it.next(), it.next(), it.next()) {
        (Some(g @ '1'..='3'), Some(l), None) if "AaBb".contains(l) => Some(UnifiedClass {
            grade: g as u8 - b'0',
            internal: l.eq_ignore_ascii_case(&'B'),
        }),
        _ => None,
    };
    ok.ok_or_else(|| {
        StandardError::new(format!(
            "expected an ASME B1.1 class: 1A, 2A, 3A (external) or 1B, 2B, 3B (internal), got `{s}`"
        ))
    })
}

/// ISO 2903 class text (`7e`, `8c`, `7H`).
pub(super) fn tr_class(s: &str) -> Result<(u8, char), StandardError> {
    match grade_letter(s) {
        Some((g, l)) if s.chars().count() == 2 && "ceCEH".contains(l) => Ok((g, l)),
        _ => Err(StandardError::new(format!(
            "expected an ISO 2903 class: 7e, 8e, 8c, 9c (external) or 7H, 8H, 9H (internal), got `{s}`"
        ))),
    }
}

fn eat_times(c: &mut Cursor) -> bool {
    c.skip_ws();
    let ok = c.eat('x') || c.eat('X') || c.eat('×');
    c.skip_ws();
    ok
}

fn metric(c: &mut Cursor) -> Result<Designation, StandardError> {
    c.i += 1;
    c.skip_ws();
    let d = c.number("the nominal diameter (mm) after M", true)?;
    let save = c.i;
    let (mut pitch, mut starts, mut pitch_text) = (None, 1u32, String::new());
    if eat_times(c) {
        if c.eat_word("Ph") {
            c.skip_ws();
            let lead = c.number("the lead (mm) after Ph", true)?;
            c.skip_ws();
            if !c.eat_word("P") {
                return Err(c.expected("P and the pitch after the lead (M16xPh3P1.5)"));
            }
            c.skip_ws();
            let p = c.number("the pitch (mm) after P", true)?;
            starts = whole_starts(c.text, lead, p)?;
            pitch = Some(p);
            pitch_text = format!("xPh{}P{}", fmt_num(lead), fmt_num(p));
        } else {
            let p = c.number("the pitch (mm) after x", true)?;
            pitch = Some(p);
            pitch_text = format!("x{}", fmt_num(p));
        }
    } else {
        c.i = save;
    }
    let p = match pitch {
        Some(p) => p,
        None => iso965::coarse_pitch(d).ok_or_else(|| {
            StandardError::new(format!(
                "`{}`: M{} has no coarse pitch in ISO 261 (coarse sizes {}); give the pitch, e.g. M{}x1.5",
                c.text,
                fmt_num(d),
                iso965::coarse_sizes(),
                fmt_num(d)
            ))
        })?,
    };
    check_pitch(c.text, d, p)?;
    let lh_early = {
        c.skip_ws();
        c.eat_word("LH")
    };
    let tl = tail(c, true, "a tolerance class (6g, 6H)")?;
    let class = match &tl.class {
        None => ClassSpec::None,
        Some((s, at)) => match s.split_once('/') {
            Some((a, b)) => {
                let i = metric_class(a).map_err(|e| at_token(c.text, *at, e))?;
                let mut e = metric_class(b).map_err(|e| at_token(c.text, *at, e))?;
                if !c.text.chars().any(char::is_lowercase) {
                    // In capitals the second class of a fit is the external one.
                    e.pitch.1 = e.pitch.1.to_ascii_lowercase();
                    e.crest.1 = e.crest.1.to_ascii_lowercase();
                }
                if !i.internal() || e.internal() {
                    return Err(token_error(
                        c.text,
                        *at,
                        "a fit written internal class first, then external: 6H/6g",
                    ));
                }
                ClassSpec::MetricFit(i, e)
            }
            None => ClassSpec::Metric(metric_class(s).map_err(|e| at_token(c.text, *at, e))?),
        },
    };
    let left_hand = lh_early || tl.left_hand;
    let engagement = tl.group.unwrap_or(Engagement::Normal);
    let mut text = format!("M{}{}", fmt_num(d), pitch_text);
    if let Some((s, _)) = &tl.class {
        text.push('-');
        text.push_str(s);
    }
    match tl.group {
        Some(Engagement::Short) => text.push_str("-S"),
        Some(Engagement::Long) => text.push_str("-L"),
        Some(Engagement::Length(v)) => text.push_str(&format!("-{}", fmt_num(v))),
        _ => {}
    }
    if left_hand {
        text.push_str("-LH");
    }
    Ok(Designation {
        text,
        standard: Standard::Metric,
        major: d,
        pitch: p,
        starts,
        left_hand,
        engagement,
        class,
        all_caps: false,
        size: String::new(),
        tpi: None,
    })
}

/// A class error with the designation and the class's position.
fn at_token(text: &str, at: usize, e: StandardError) -> StandardError {
    StandardError::new(format!("`{text}` (character {}): {}", at + 1, e.message))
}

fn whole_starts(text: &str, lead: f64, p: f64) -> Result<u32, StandardError> {
    let n = lead / p;
    if (n - n.round()).abs() > 1e-9 || n.round() < 1.0 || n.round() > 64.0 {
        return Err(StandardError::new(format!(
            "`{text}`: expected the lead to be 1 to 64 times the pitch (the number of starts), got {} / {}",
            fmt_num(lead),
            fmt_num(p)
        )));
    }
    Ok(n.round() as u32)
}

fn check_pitch(text: &str, d: f64, p: f64) -> Result<(), StandardError> {
    if p >= d / 2.0 || d > 10_000.0 {
        return Err(StandardError::new(format!(
            "`{text}`: expected a pitch less than half the diameter and a diameter up to 10 m, got diameter {} and pitch {}",
            fmt_num(d),
            fmt_num(p)
        )));
    }
    Ok(())
}

fn trapezoidal(c: &mut Cursor) -> Result<Designation, StandardError> {
    c.i += 2;
    c.skip_ws();
    let d = c.number("the nominal diameter (mm) after Tr", true)?;
    if !eat_times(c) {
        return Err(c.expected("x and the pitch (Tr40x7) or the lead (Tr40x14(P7))"));
    }
    let lead = c.number("the pitch or lead (mm) after x", true)?;
    c.skip_ws();
    let (p, starts, mut text) = if c.eat('(') {
        c.skip_ws();
        if !c.eat_word("P") {
            return Err(c.expected("P and the pitch: Tr40x14(P7)"));
        }
        c.skip_ws();
        let p = c.number("the pitch (mm) after (P", true)?;
        c.skip_ws();
        if !c.eat(')') {
            return Err(c.expected("`)` after the pitch"));
        }
        let n = whole_starts(c.text, lead, p)?;
        (
            p,
            n,
            format!("Tr{}x{}(P{})", fmt_num(d), fmt_num(lead), fmt_num(p)),
        )
    } else {
        (lead, 1, format!("Tr{}x{}", fmt_num(d), fmt_num(lead)))
    };
    check_pitch(c.text, d, p)?;
    c.skip_ws();
    let lh_early = c.eat_word("LH");
    let tl = tail(c, false, "a tolerance class (7e, 7H)")?;
    let class = match &tl.class {
        None => ClassSpec::None,
        Some((s, at)) => match s.split_once('/') {
            Some((a, b)) => {
                let i = tr_class(a).map_err(|e| at_token(c.text, *at, e))?;
                let e = tr_class(b).map_err(|e| at_token(c.text, *at, e))?;
                if i.1 != 'H' || e.1 == 'H' {
                    return Err(token_error(
                        c.text,
                        *at,
                        "a fit written internal class first, then external: 7H/7e",
                    ));
                }
                ClassSpec::TrapezoidalFit(i, (e.0, e.1.to_ascii_lowercase()))
            }
            None => {
                let (g, l) = tr_class(s).map_err(|e| at_token(c.text, *at, e))?;
                ClassSpec::Trapezoidal(g, l)
            }
        },
    };
    let left_hand = lh_early || tl.left_hand;
    if let Some((s, _)) = &tl.class {
        text.push('-');
        text.push_str(s);
    }
    if left_hand {
        text.push_str("-LH");
    }
    Ok(Designation {
        text,
        standard: Standard::Trapezoidal,
        major: d,
        pitch: p,
        starts,
        left_hand,
        engagement: Engagement::Normal,
        class,
        all_caps: false,
        size: String::new(),
        tpi: None,
    })
}

/// An inch size: `#10`, `1/2`, `1 1/4`, `1-1/4`, `1`, `0.250`: (inches, as written
/// normalised). `hyphen_mixed`: `1-1/4` may be a mixed number (not when the `-` leads to
/// the threads per inch).
fn inch_size(c: &mut Cursor) -> Result<(f64, String), StandardError> {
    if c.eat('#') {
        let n = c.integer("a number size after # (#0 to #12)")?;
        if n > 12 {
            c.i -= 1;
            return Err(StandardError::new(format!(
                "`{}`: expected a number size #0 to #12 (ASME B1.1), got #{n}",
                c.text
            )));
        }
        return Ok((0.060 + 0.013 * n as f64, format!("#{n}")));
    }
    if c.peek() == Some('.') {
        let v = c.number("an inch size", false)?;
        return Ok((v, fmt_num(v)));
    }
    let start = c.i;
    let whole = c.integer("an inch size (1/2, 1, 1 1/4, #10)")?;
    if c.peek() == Some('.') {
        c.i = start;
        let v = c.number("an inch size", false)?;
        return Ok((v, fmt_num(v)));
    }
    if c.eat('/') {
        let den = c.integer("the denominator of the size's fraction")?;
        return fraction(c, 0, whole, den, start);
    }
    // A mixed number: `1 1/4` or `1-1/4` (a fraction follows the space or hyphen).
    let save = c.i;
    if c.peek().is_some_and(|ch| ch == ' ' || ch == '-') {
        c.i += 1;
        c.skip_ws();
        let num_start = c.i;
        if let Ok(num) = c.integer("") {
            if c.eat('/') {
                let den = c.integer("the denominator of the size's fraction")?;
                if num >= den {
                    c.i = num_start;
                    return Err(c.expected("a proper fraction after the whole inches (1 1/4)"));
                }
                return fraction(c, whole, num, den, start);
            }
        }
        c.i = save;
    }
    if whole == 0 {
        c.i = start;
        return Err(c.expected("an inch size greater than 0"));
    }
    Ok((whole as f64, whole.to_string()))
}

fn fraction(
    c: &mut Cursor,
    whole: u32,
    num: u32,
    den: u32,
    start: usize,
) -> Result<(f64, String), StandardError> {
    if den == 0 || num == 0 {
        c.i = start;
        return Err(c.expected("a size fraction with a non-zero numerator and denominator"));
    }
    let v = whole as f64 + num as f64 / den as f64;
    let text = if whole > 0 {
        format!("{whole} {num}/{den}")
    } else {
        format!("{num}/{den}")
    };
    Ok((v, text))
}

fn inch(c: &mut Cursor) -> Result<Designation, StandardError> {
    let (d, size) = inch_size(c)?;
    c.skip_ws();
    let tpi = if c.eat('-') {
        c.skip_ws();
        Some(c.number("the threads per inch after `-`", false)?)
    } else if c.peek().is_some_and(|ch| ch.is_ascii_alphabetic()) {
        None
    } else {
        return Err(c.expected("`-` and the threads per inch (1/2-13 UNC)"));
    };
    c.skip_ws();
    let start = c.i;
    let mut letters = String::new();
    while let Some(ch) = c.peek().filter(char::is_ascii_alphabetic) {
        letters.push(ch.to_ascii_uppercase());
        c.i += 1;
    }
    let standard = match letters.as_str() {
        "UNC" => Standard::Unified(Series::Coarse),
        "UNF" => Standard::Unified(Series::Fine),
        "UNEF" => Standard::Unified(Series::ExtraFine),
        "UN" => Standard::Unified(Series::Constant),
        "UNS" => Standard::Unified(Series::Special),
        "ACME" => Standard::Acme,
        "NPT" => Standard::Npt,
        _ => {
            c.i = start;
            return Err(c.expected("the series: UNC, UNF, UNEF, UN, UNS, ACME or NPT"));
        }
    };
    let tpi = match (tpi, standard) {
        (Some(t), _) => t,
        (None, Standard::Npt) => match pipe::npt_size(&size) {
            Some((_, n, _)) => n,
            None => return Err(npt_size_error(c.text, &size)),
        },
        (None, _) => {
            c.i = start;
            return Err(c.expected("`-` and the threads per inch before the series (1/2-13 UNC)"));
        }
    };
    let tl = tail(c, false, "a class (2A, 2B)")?;
    let (major, class) = match standard {
        Standard::Unified(series) => {
            unified::check_series(series, d, tpi, &size)
                .map_err(|m| StandardError::new(format!("`{}`: {m}", c.text)))?;
            let class = match &tl.class {
                None => ClassSpec::None,
                Some((s, at)) => {
                    ClassSpec::Unified(unified_class(s).map_err(|e| at_token(c.text, *at, e))?)
                }
            };
            (d * 25.4, class)
        }
        Standard::Acme => {
            let class = match &tl.class {
                None => ClassSpec::None,
                Some((s, _)) => ClassSpec::Acme(s.to_ascii_uppercase()),
            };
            (d * 25.4, class)
        }
        _ => {
            let Some((od, n, _)) = pipe::npt_size(&size) else {
                return Err(npt_size_error(c.text, &size));
            };
            if (n - tpi).abs() > 1e-9 {
                return Err(StandardError::new(format!(
                    "`{}`: {size} NPT has {} threads per inch (ASME B1.20.1), not {}",
                    c.text,
                    fmt_num(n),
                    fmt_num(tpi)
                )));
            }
            if let Some((s, at)) = &tl.class {
                return Err(token_error(
                    c.text,
                    *at,
                    &format!("no class after NPT (B1.20.1 has none), not `{s}`"),
                ));
            }
            let (_, e1) = pipe::npt_e0_e1(od, n, pipe::npt_size(&size).map_or(0.0, |s| s.2));
            ((e1 + 0.8 / n) * 25.4, ClassSpec::None)
        }
    };
    let p = 25.4 / tpi;
    check_pitch(c.text, major, p)?;
    let mut text = format!("{size}-{} {letters}", fmt_num(tpi));
    if let Some((s, _)) = &tl.class {
        text.push('-');
        text.push_str(&s.to_ascii_uppercase());
    }
    if tl.left_hand {
        text.push_str("-LH");
    }
    Ok(Designation {
        text,
        standard,
        major,
        pitch: p,
        starts: 1,
        left_hand: tl.left_hand,
        engagement: Engagement::Normal,
        class,
        all_caps: false,
        size,
        tpi: Some(tpi),
    })
}

fn npt_size_error(text: &str, size: &str) -> StandardError {
    StandardError::new(format!(
        "`{text}`: {size} is not an NPT size (ASME B1.20.1: {})",
        pipe::sizes('N')
    ))
}

fn pipe_g(c: &mut Cursor) -> Result<Designation, StandardError> {
    c.i += 1;
    c.skip_ws();
    let (_, size) = inch_size(c)?;
    let Some((n, d, _)) = pipe::g_size(&size) else {
        return Err(StandardError::new(format!(
            "`{}`: G{size} is not an ISO 228-1 size ({})",
            c.text,
            pipe::sizes('G')
        )));
    };
    c.skip_ws();
    let mut class = ClassSpec::None;
    if let Some(l) = c.peek().filter(|l| "AaBb".contains(*l)) {
        if !c.peek_at(1).is_some_and(|n| n.is_ascii_alphanumeric()) {
            class = ClassSpec::Pipe(l.to_ascii_uppercase());
            c.i += 1;
        }
    }
    let tl = tail(c, false, "the class A or B (ISO 228-1)")?;
    if let Some((s, at)) = &tl.class {
        return Err(token_error(
            c.text,
            *at,
            &format!("the class A or B (ISO 228-1), not `{s}`"),
        ));
    }
    let mut text = format!("G{size}");
    if let ClassSpec::Pipe(l) = class {
        text.push(' ');
        text.push(l);
    }
    if tl.left_hand {
        text.push_str("-LH");
    }
    Ok(Designation {
        text,
        standard: Standard::PipeParallel,
        major: d,
        pitch: 25.4 / n,
        starts: 1,
        left_hand: tl.left_hand,
        engagement: Engagement::Normal,
        class,
        all_caps: false,
        size,
        tpi: Some(n),
    })
}

fn pipe_r(c: &mut Cursor) -> Result<Designation, StandardError> {
    c.i += 1;
    let (standard, symbol) = if c.eat('c') || c.eat('C') {
        (Standard::PipeTaper { internal: true }, "Rc")
    } else if c.eat('p') || c.eat('P') {
        (Standard::PipeParallelInternal, "Rp")
    } else {
        (Standard::PipeTaper { internal: false }, "R")
    };
    c.skip_ws();
    if !c.peek().is_some_and(|ch| ch.is_ascii_digit()) {
        return Err(c.expected("a pipe size after R, Rc or Rp (R1/2)"));
    }
    let (_, size) = inch_size(c)?;
    let g = pipe::g_size(&size).filter(|_| pipe::r_size(&size));
    let Some((n, d, _)) = g else {
        return Err(StandardError::new(format!(
            "`{}`: {symbol}{size} is not an ISO 7-1 size ({})",
            c.text,
            pipe::sizes('R')
        )));
    };
    let tl = tail(c, false, "no class (ISO 7-1 has none)")?;
    if let Some((s, at)) = &tl.class {
        return Err(token_error(
            c.text,
            *at,
            &format!("no class after {symbol}{size} (ISO 7-1 has none), not `{s}`"),
        ));
    }
    let mut text = format!("{symbol}{size}");
    if tl.left_hand {
        text.push_str("-LH");
    }
    Ok(Designation {
        text,
        standard,
        major: d,
        pitch: 25.4 / n,
        starts: 1,
        left_hand: tl.left_hand,
        engagement: Engagement::Normal,
        class: ClassSpec::None,
        all_caps: false,
        size,
        tpi: Some(n),
    })
}

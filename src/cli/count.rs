//! Counts on the command line as they are written on a shop floor: the dexel budget
//! (`--max-dexels 4e8`), read by the same rule as the job's `[simulation] max_dexels`.

/// The largest dexel budget (the job key's range): 4 PB.
const MAX_DEXEL_BUDGET: f64 = 1e15;

/// A dexel budget as a count is written on a shop floor: `400000000`, `400_000_000` (an
/// underscore only between digits, as in TOML), or scientific notation that is a whole
/// number (`4e8`, `4.0e8`, `2.5E8`); from 0 (which refuses every run and says what it
/// would hold) to 1e15. Not negatives, fractions (`1.5`), `nan` or `inf`.
pub(crate) fn parse_dexels(s: &str) -> Result<u64, String> {
    let bytes = s.as_bytes();
    let digit = |k: usize| bytes.get(k).is_some_and(u8::is_ascii_digit);
    let underscores_ok = bytes
        .iter()
        .enumerate()
        .all(|(k, &b)| b != b'_' || (k > 0 && digit(k - 1) && digit(k + 1)));
    let numeric = !s.is_empty()
        && underscores_ok
        && s.bytes()
            .all(|b| b.is_ascii_digit() || b"_.eE+-".contains(&b))
        && s.bytes().any(|b| b.is_ascii_digit());
    let clean = s.replace('_', "");
    let value = match clean.parse::<f64>() {
        Ok(v) if numeric => v,
        _ => {
            return Err(format!(
                "expected a whole number of dexels (400000000, 400_000_000 or 4e8), not `{s}`"
            ))
        }
    };
    if !(0.0..=MAX_DEXEL_BUDGET).contains(&value) {
        return Err(format!(
            "expected a number of dexels from 0 to 1e15, not `{s}`"
        ));
    }
    if value.fract() != 0.0 {
        return Err(format!(
            "expected a whole number of dexels, not `{s}` (a dexel is 4 bytes)"
        ));
    }
    // A plain integer is read exactly; a float that is whole and at most 1e15 is exact.
    Ok(clean.parse::<u64>().unwrap_or(value as u64))
}

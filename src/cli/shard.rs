//! `vpcut check --shard I/N`: the job list split for a CI matrix (GitHub Actions'
//! `strategy.matrix`, GitLab's `parallel`), deterministically whatever order the shell
//! gave the files in: the jobs sorted by their path as given, then dealt round robin, the
//! k-th (0-based) to shard `k mod N + 1`. The N shards together are the list, each job in
//! exactly one; they differ in size by at most one job.

use std::path::Path;

/// A shard: the I-th (1-based) of N.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Shard {
    /// Which one, 1..=n.
    pub(crate) index: usize,
    /// How many.
    pub(crate) count: usize,
}

/// `I/N` as written on the command line.
pub(crate) fn parse_shard(s: &str) -> Result<Shard, String> {
    let want = "expected I/N: shard I of N, whole numbers with 1 <= I <= N (e.g. 2/4)";
    let (i, n) = s.split_once('/').ok_or_else(|| format!("`{s}`: {want}"))?;
    let num = |t: &str| t.trim().parse::<usize>().ok();
    match (num(i), num(n)) {
        (Some(index), Some(count)) if index >= 1 && index <= count => Ok(Shard { index, count }),
        _ => Err(format!("`{s}`: {want}")),
    }
}

/// The jobs of `shard`, in sorted order.
pub(crate) fn select<'a>(jobs: &[&'a Path], shard: Shard) -> Vec<&'a Path> {
    let mut sorted = jobs.to_vec();
    sorted.sort();
    sorted.dedup();
    sorted
        .into_iter()
        .enumerate()
        .filter(|(k, _)| k % shard.count + 1 == shard.index)
        .map(|(_, p)| p)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shard_specs_are_checked() {
        assert_eq!(parse_shard("2/4"), Ok(Shard { index: 2, count: 4 }));
        assert_eq!(parse_shard("1/1"), Ok(Shard { index: 1, count: 1 }));
        for bad in ["0/4", "5/4", "2", "a/b", "2/0", "-1/3", "1/"] {
            let e = parse_shard(bad).unwrap_err();
            assert!(e.contains("expected I/N") && e.contains(bad), "{bad}: {e}");
        }
    }

    /// Random lists (seeded) in random orders: the shards of every N cover the list once,
    /// differ in size by at most one, and do not depend on the order given.
    #[test]
    fn shards_partition_the_list_whatever_its_order() {
        let mut x: u64 = 0x2929;
        let mut next = move || {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            x
        };
        for _ in 0..50 {
            let len = (next() % 40) as usize;
            let names: Vec<String> = (0..len)
                .map(|i| format!("jobs/j{}.toml", i * 7 % 41))
                .collect();
            let mut shuffled = names.clone();
            for i in (1..shuffled.len()).rev() {
                shuffled.swap(i, (next() % (i as u64 + 1)) as usize);
            }
            let a: Vec<&Path> = names.iter().map(Path::new).collect();
            let b: Vec<&Path> = shuffled.iter().map(Path::new).collect();
            for count in 1..=7 {
                let mut all = Vec::new();
                let mut sizes = Vec::new();
                for index in 1..=count {
                    let s = Shard { index, count };
                    let got = select(&a, s);
                    assert_eq!(got, select(&b, s));
                    sizes.push(got.len());
                    all.extend(got);
                }
                all.sort();
                let mut want = a.clone();
                want.sort();
                assert_eq!(all, want);
                let (lo, hi) = (sizes.iter().min().unwrap(), sizes.iter().max().unwrap());
                assert!(hi - lo <= 1, "{sizes:?}");
            }
        }
    }
}

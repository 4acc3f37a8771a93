//! `solver.threads`: how many threads step a drive (docs/model.md, "Two
//! threads for large drives").

use serde::{Deserialize, Serialize};

/// Drive size from which `threads = "auto"` splits the rollers over two
/// threads: below it the fork and join of every roller loop cost more than
/// the half loop saves. Measured on an idle 2-core machine: two threads
/// break even at 5,000 rollers and gain 1.2× at 7,000 and 10,000
/// (benches/README.md, "Two threads").
pub(crate) const AUTO_MIN_ROLLERS: usize = 6000;

/// How many threads step the drive's roller loops (links, the rollers'
/// update). The results are the same bits on one thread or two.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Threads {
    /// Two threads from `AUTO_MIN_ROLLERS` rollers on a machine with two
    /// cores or more, else one (the default).
    #[default]
    Auto,
    /// One thread.
    One,
    /// Two threads (for drives of at least 16 rollers).
    Two,
}

impl Threads {
    /// The threads a drive of `rollers` rollers uses on this machine.
    pub fn count(self, rollers: usize) -> usize {
        let two = match self {
            Self::One => false,
            Self::Two => true,
            Self::Auto => {
                rollers >= AUTO_MIN_ROLLERS
                    && std::thread::available_parallelism().map_or(1, |n| n.get()) >= 2
            }
        };
        if two && rollers >= 16 { 2 } else { 1 }
    }

    /// From the file's value: 1, 2 or `"auto"`; the error says what is allowed.
    pub(crate) fn from_file(f: &ThreadsFile) -> Result<Self, String> {
        match f {
            ThreadsFile::Count(1) => Ok(Self::One),
            ThreadsFile::Count(2) => Ok(Self::Two),
            ThreadsFile::Word(w) if w == "auto" => Ok(Self::Auto),
            ThreadsFile::Count(n) => Err(format!("must be 1, 2 or \"auto\", got {n}")),
            ThreadsFile::Word(w) => Err(format!("must be 1, 2 or \"auto\", got \"{w}\"")),
        }
    }
}

impl std::str::FromStr for Threads {
    type Err = String;

    /// `1`, `2` or `auto`.
    fn from_str(s: &str) -> Result<Self, String> {
        let f = match s.trim().parse::<i64>() {
            Ok(n) => ThreadsFile::Count(n),
            Err(_) => ThreadsFile::Word(s.trim().to_owned()),
        };
        Self::from_file(&f).map_err(|e| format!("threads {e}"))
    }
}

/// `solver.threads` as written: 1, 2 or the word `"auto"` (the default).
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(untagged)]
pub enum ThreadsFile {
    /// A thread count.
    Count(i64),
    /// A word; only `"auto"` is valid.
    Word(String),
}

impl Default for ThreadsFile {
    fn default() -> Self {
        Self::Word("auto".to_owned())
    }
}

impl ThreadsFile {
    /// Whether this is the default, `"auto"` (left out when a scene is written).
    pub fn is_auto(&self) -> bool {
        matches!(self, Self::Word(w) if w == "auto")
    }
}

impl From<Threads> for ThreadsFile {
    fn from(t: Threads) -> Self {
        match t {
            Threads::Auto => Self::default(),
            Threads::One => Self::Count(1),
            Threads::Two => Self::Count(2),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_setting_reads_one_two_and_auto_and_names_what_is_allowed() {
        assert_eq!("1".parse::<Threads>(), Ok(Threads::One));
        assert_eq!("2".parse::<Threads>(), Ok(Threads::Two));
        assert_eq!("auto".parse::<Threads>(), Ok(Threads::Auto));
        let e = "3"
            .parse::<Threads>()
            .expect_err("3 threads is not offered");
        assert!(e.contains("1, 2 or \"auto\""), "{e}");
        assert_eq!(Threads::One.count(100_000), 1);
        assert_eq!(Threads::Two.count(3), 1);
        assert_eq!(Threads::Two.count(100), 2);
    }
}

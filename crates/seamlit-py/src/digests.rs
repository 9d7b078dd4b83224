//! The report's SHA-256 digests of a Ray task's files, made together at the end of the task
//! instead of one file after another: several messages hashed at once run side by side in
//! the CPU's vector lanes (or its SHA units' parallel streams), which one message cannot
//! (each of its blocks needs the one before). Hashing every input and output of
//! `bench/ray_fleet.py`'s library one after another took 28% of folder mode's time to fix
//! it; as groups of sixteen messages of about one size, 2.6 times less (BENCHMARKS.md).
//!
//! [`Digests`] is what Python holds: the files and bytes still to hash, each under a key of
//! the caller's; [`Digests::take`] hashes them all and hands back each key's digest.
//!
//! Lanes run in step: a group is as slow as its longest message, so a group holds messages
//! of about one length ([`groups`]); one without a partner is hashed alone (`sha2`).
//!
//! A file is read when it is hashed, later than when it was added (or fixed): it is hashed
//! only if it is still the file it was then ([`Stamp`]: its length, modification time and
//! inode), else it has no digest. A report must not hold the hash of bytes that were not the
//! ones fixed: a second run would take the file as fixed and skip it.

use std::path::{Path, PathBuf};
use std::time::SystemTime;

use pyo3::prelude::*;
use sha2::{Digest, Sha256};

/// A message to hash: a file (read when hashed, if it is still as stamped) or bytes already
/// in memory.
enum Message {
    File(PathBuf, Stamp),
    Bytes(Vec<u8>),
    /// A file that could not be read when it was added: no digest.
    Gone,
}

/// What a file was at one moment: its length, modification time and (on Unix) device and
/// inode. A file replaced by another, or written since to another length, has another
/// stamp; one rewritten in place to the same length has another modification time unless
/// both writes fall in one tick of the clock Linux stamps files with (a few milliseconds).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Stamp {
    len: u64,
    modified: Option<SystemTime>,
    inode: (u64, u64),
}

impl Stamp {
    /// The stamp of the file at `path` now.
    pub(crate) fn of(path: &Path) -> std::io::Result<Self> {
        std::fs::metadata(path).map(|m| Self::from(&m))
    }
}

impl From<&std::fs::Metadata> for Stamp {
    fn from(metadata: &std::fs::Metadata) -> Self {
        #[cfg(unix)]
        let inode = {
            use std::os::unix::fs::MetadataExt;
            (metadata.dev(), metadata.ino())
        };
        #[cfg(not(unix))]
        let inode = (0, 0);
        Self { len: metadata.len(), modified: metadata.modified().ok(), inode }
    }
}

/// Files and bytes whose SHA-256 the caller wants, each under its key, hashed together by
/// [`Self::take`].
#[pyclass(module = "seamlit._seamlit")]
#[derive(Default)]
pub(crate) struct Digests {
    pending: Vec<(u64, Message)>,
    /// The bytes held in memory (files are read when hashed).
    held: usize,
}

impl Digests {
    /// Adds `bytes` under `key`.
    pub(crate) fn push_bytes(&mut self, key: u64, bytes: Vec<u8>) {
        self.held += bytes.len();
        self.pending.push((key, Message::Bytes(bytes)));
    }

    /// Adds the file at `path` under `key`, to be hashed if it is still as `stamp` says
    /// (taken before the file was read for what the digest stands for).
    pub(crate) fn push_file(&mut self, key: u64, path: PathBuf, stamp: Stamp) {
        self.pending.push((key, Message::File(path, stamp)));
    }

    /// Adds `key` without a message: its digest is `None`.
    pub(crate) fn push_gone(&mut self, key: u64) {
        self.pending.push((key, Message::Gone));
    }
}

#[pymethods]
impl Digests {
    #[new]
    fn new() -> Self {
        Self::default()
    }

    /// Adds the file at `path` under `key` as it is now: read when [`Self::take`] hashes it,
    /// without a digest if it has changed by then.
    fn add_file(&mut self, key: u64, path: PathBuf) {
        match Stamp::of(&path) {
            Ok(stamp) => self.push_file(key, path, stamp),
            Err(_) => self.push_gone(key),
        }
    }

    /// Adds a copy of `data` under `key`.
    fn add_bytes(&mut self, key: u64, data: &[u8]) {
        self.push_bytes(key, data.to_vec());
    }

    /// The bytes held in memory until [`Self::take`].
    fn held(&self) -> usize {
        self.held
    }

    /// How many messages wait to be hashed.
    fn __len__(&self) -> usize {
        self.pending.len()
    }

    /// Hashes everything added and empties the set: each key with its digest in lowercase
    /// hex (as `hashlib` writes it), or `None` for a file that can no longer be read or is
    /// no longer the file it was when added.
    fn take(&mut self, py: Python<'_>) -> Vec<(u64, Option<String>)> {
        let pending = std::mem::take(&mut self.pending);
        self.held = 0;
        py.detach(|| hash_all(pending))
    }
}

/// Each message's digest, under its key, in the order given.
fn hash_all(pending: Vec<(u64, Message)>) -> Vec<(u64, Option<String>)> {
    let lengths: Vec<Option<usize>> = pending.iter().map(|(_, m)| length(m)).collect();
    let mut digests: Vec<Option<String>> = vec![None; pending.len()];
    // Files are read into the same buffers group after group: fresh memory for each file
    // (page faults, zeroing) cost as much as hashing it.
    let mut buffers: Vec<Vec<u8>> = Vec::new();
    for group in groups(&lengths, tape_sha256::lane_width()) {
        buffers.resize_with(buffers.len().max(group.len()), Vec::new);
        // A file that fails to read keeps no digest.
        let read: Vec<bool> = group
            .iter()
            .zip(buffers.iter_mut())
            .map(|(&i, buffer)| match &pending[i].1 {
                Message::Bytes(_) => true,
                Message::File(path, stamp) => read_unchanged(path, *stamp, buffer),
                Message::Gone => false,
            })
            .collect();
        let messages: Vec<(usize, &[u8])> = group
            .iter()
            .zip(&buffers)
            .zip(&read)
            .filter(|(_, ok)| **ok)
            .map(|((&i, buffer), _)| match &pending[i].1 {
                Message::Bytes(bytes) => (i, &bytes[..]),
                Message::File(..) | Message::Gone => (i, &buffer[..]),
            })
            .collect();
        let slices: Vec<&[u8]> = messages.iter().map(|(_, bytes)| *bytes).collect();
        let mut out = vec![[0u8; 32]; slices.len()];
        if let [one] = slices[..] {
            out[0] = Sha256::digest(one).into();
        } else if !slices.is_empty() {
            tape_sha256::hash_many(&slices, &mut out);
        }
        for ((i, _), digest) in messages.iter().zip(&out) {
            digests[*i] = Some(hex(digest));
        }
    }
    pending.into_iter().map(|(key, _)| key).zip(digests).collect()
}

/// The message's length (a file's from its stamp), `None` for a file that cannot be read or
/// is no longer as stamped.
fn length(message: &Message) -> Option<usize> {
    match message {
        Message::Bytes(bytes) => Some(bytes.len()),
        Message::File(path, stamp) => (Stamp::of(path).ok() == Some(*stamp))
            .then(|| usize::try_from(stamp.len).ok())
            .flatten(),
        Message::Gone => None,
    }
}

/// Reads the file at `path` into `buffer`, in the memory it already has; whether it read the
/// file as `stamp` says it was, before and after the read (a file written meanwhile is not).
fn read_unchanged(path: &Path, stamp: Stamp, buffer: &mut Vec<u8>) -> bool {
    use std::io::Read;
    buffer.clear();
    let Ok(mut file) = std::fs::File::open(path) else { return false };
    let before = file.metadata().map(|m| Stamp::from(&m)).ok();
    let read = file.read_to_end(buffer).is_ok();
    let after = file.metadata().map(|m| Stamp::from(&m)).ok();
    read && before == Some(stamp) && after == Some(stamp) && buffer.len() as u64 == stamp.len
}

/// How much longer than the shortest of its group a message may be (its group runs as
/// long as its longest lane): an eighth, or one 4 KiB page for small messages.
fn fits(shortest: usize, length: usize) -> bool {
    length <= shortest + (shortest / 8).max(4096)
}

/// The messages (by index into `lengths`) in groups of at most `lanes` of about one length
/// (see [`fits`]), shortest first; messages whose length is `None` alone. Every message is
/// in exactly one group.
fn groups(lengths: &[Option<usize>], lanes: usize) -> Vec<Vec<usize>> {
    let mut order: Vec<usize> = (0..lengths.len()).collect();
    order.sort_by_key(|&i| lengths[i]);
    let mut groups: Vec<Vec<usize>> = Vec::new();
    let mut shortest = 0;
    for i in order {
        match (lengths[i], groups.last_mut()) {
            (Some(n), Some(group))
                if group.len() < lanes.max(1)
                    && lengths[group[0]].is_some()
                    && fits(shortest, n) =>
            {
                group.push(i);
            }
            (n, _) => {
                shortest = n.unwrap_or(0);
                groups.push(vec![i]);
            }
        }
    }
    groups
}

/// A digest in lowercase hex.
pub(crate) fn hex(digest: &[u8]) -> String {
    use std::fmt::Write;
    digest.iter().fold(String::with_capacity(2 * digest.len()), |mut hex, byte| {
        let _ = write!(hex, "{byte:02x}");
        hex
    })
}

/// The SHA-256 of `bytes`, in lowercase hex (as Python's `hashlib` writes it).
pub(crate) fn sha256(bytes: &[u8]) -> String {
    hex(&Sha256::digest(bytes))
}

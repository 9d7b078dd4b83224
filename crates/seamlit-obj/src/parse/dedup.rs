//! An object's vertices: the distinct `v/vt/vn` triples of its corners in order of first use,
//! tobj's rule for what a vertex is (tobj keeps a hash map per object). Most files have one
//! vertex per position, so a table indexed by position, with a chain for the others, answers
//! in one memory access; files whose positions are spread thin, or with many `vt` / `vn` per
//! position, use a hash map keyed by the packed triple, hashed with splitmix64's finaliser
//! (G. L. Steele, D. Lea, C. H. Flood, "Fast splittable pseudorandom number generators",
//! OOPSLA 2014).

use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};

use super::corners::Corner;

/// The distinct corners in order of first use, and the triangles as indices among them.
type Dedup = (Vec<Corner>, Vec<[u32; 3]>);

/// Deduplicates the corners of `triangles` (`count` of them) with a table indexed by
/// position holding the first vertex at that position (its id, `vt` and `vn`: one memory
/// access for the common case of one vertex per position) and a chain of the others; `None`
/// (try [`hashed_dedup`]) when the positions used are spread too thin for a table or a
/// chain grows long (many `vt` / `vn` per position: a hash map bounds the work of such a
/// file).
pub(super) fn dense_dedup<'a>(
    triangles: impl Iterator<Item = &'a [Corner; 3]> + Clone,
    count: usize,
) -> Option<Dedup> {
    const NONE: u32 = u32::MAX;
    const LONGEST_CHAIN: usize = 32;
    let (low, high) = triangles
        .clone()
        .flatten()
        .fold((u32::MAX, 0), |(low, high), c| (low.min(c[0]), high.max(c[0])));
    if low > high {
        return Some((Vec::new(), Vec::new()));
    }
    let span = (high - low) as usize + 1;
    if span > 6 * count + 1024 {
        return None;
    }
    // Per position: [first vertex, its vt, its vn].
    let mut first = vec![[NONE; 3]; span];
    let mut keys: Vec<Corner> = Vec::with_capacity(count / 2 + 16);
    // Per vertex: the next vertex at the same position.
    let mut next: Vec<u32> = Vec::with_capacity(count / 2 + 16);
    let mut out: Vec<[u32; 3]> = Vec::with_capacity(count);
    for triangle in triangles {
        let mut indices = [0; 3];
        for (index, &key) in indices.iter_mut().zip(triangle) {
            let head = &mut first[(key[0] - low) as usize];
            if head[0] != NONE && head[1] == key[1] && head[2] == key[2] {
                *index = head[0];
                continue;
            }
            let mut at = if head[0] == NONE { NONE } else { next[head[0] as usize] };
            let mut steps = 0;
            while at != NONE {
                let known = keys[at as usize];
                if known[1] == key[1] && known[2] == key[2] {
                    break;
                }
                at = next[at as usize];
                steps += 1;
                if steps > LONGEST_CHAIN {
                    return None;
                }
            }
            if at == NONE {
                at = vertex_index(keys.len());
                keys.push(key);
                if head[0] == NONE {
                    *head = [at, key[1], key[2]];
                    next.push(NONE);
                } else {
                    // Second and later vertices at a position: after the first.
                    let second = &mut next[head[0] as usize];
                    let after = *second;
                    *second = at;
                    next.push(after);
                }
            }
            *index = at;
        }
        out.push(indices);
    }
    Some((keys, out))
}

/// Deduplicates the corners of `triangles` (`count` of them) with a hash map.
pub(super) fn hashed_dedup<'a>(
    triangles: impl Iterator<Item = &'a [Corner; 3]>,
    count: usize,
) -> Dedup {
    let mut map: HashMap<u128, u32, BuildHasherDefault<KeyHasher>> =
        HashMap::with_capacity_and_hasher(count, BuildHasherDefault::default());
    let mut keys: Vec<Corner> = Vec::with_capacity(count);
    let out = triangles
        .map(|triangle| {
            triangle.map(|key| {
                let packed =
                    u128::from(key[0]) | u128::from(key[1]) << 32 | u128::from(key[2]) << 64;
                *map.entry(packed).or_insert_with(|| {
                    keys.push(key);
                    vertex_index(keys.len() - 1)
                })
            })
        })
        .collect();
    (keys, out)
}

/// `i`, a vertex of an object, as a `u32` below [`u32::MAX`] (the tables' "none"): an object
/// has at most one vertex per triangle corner, and `obj::build_objects` refuses files of
/// `u32::MAX` corners or more before deduplicating.
#[inline]
#[expect(
    clippy::cast_possible_truncation,
    reason = "below u32::MAX: checked by obj::build_objects"
)]
fn vertex_index(i: usize) -> u32 {
    debug_assert!(i < u32::MAX as usize, "{i} vertices in one object");
    i as u32
}

/// A hasher for packed `(v, vt, vn)` keys: two multiplications and shifts (splitmix64's
/// finaliser) instead of SipHash, which took a tenth of the loading time. The keys come
/// from the file, but a collision-heavy file only slows its own loading down.
#[derive(Default)]
struct KeyHasher(u64);

impl Hasher for KeyHasher {
    fn finish(&self) -> u64 {
        self.0
    }
    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.0 = (self.0 ^ u64::from(b)).wrapping_mul(0x100_0000_01b3);
        }
    }
    fn write_u128(&mut self, key: u128) {
        // The key's two halves, each cut to 64 bits.
        let mut h = ((key & 0xFFFF_FFFF_FFFF_FFFF) as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15)
            ^ ((key >> 64) as u64).wrapping_mul(0xC2B2_AE3D_27D4_EB4F);
        h ^= h >> 29;
        h = h.wrapping_mul(0xBF58_476D_1CE4_E5B9);
        self.0 = h ^ (h >> 32);
    }
}

//! Arrays written little-endian into a file a chunk at a time, never assembled whole in
//! memory: the writers' parts (`write/bin.rs`) and the pass-through's pieces
//! (`passthrough/piece.rs`).

use std::io::{self, Write};

/// Elements encoded at a time before they are written: 4,096 tangents are 64 KiB. Written an
/// element at a time, the writer's buffer copied a few bytes per call, most of the writer's
/// time.
pub(crate) const CHUNK: usize = 4096;

/// Writes `items`, each as `encode` gives its little-endian words, [`CHUNK`] at a time (the
/// words are the file's bytes in memory: a chunk is written as it lies).
pub(crate) fn chunked<T, E: bytemuck::Pod>(
    out: &mut dyn Write,
    items: &[T],
    encode: impl Fn(&T) -> E,
) -> io::Result<()> {
    each_chunk(items, encode, |bytes| out.write_all(bytes))
}

/// Gives `each` the bytes of `items` encoded as [`chunked`] writes them, a chunk at a time.
pub(crate) fn each_chunk<T, E: bytemuck::Pod>(
    items: &[T],
    encode: impl Fn(&T) -> E,
    mut each: impl FnMut(&[u8]) -> io::Result<()>,
) -> io::Result<()> {
    let mut chunk: Vec<E> = Vec::with_capacity(items.len().min(CHUNK));
    for part in items.chunks(CHUNK) {
        chunk.clear();
        chunk.extend(part.iter().map(&encode));
        each(bytemuck::cast_slice(&chunk))?;
    }
    Ok(())
}

/// `values` as little-endian words: on a little-endian machine, their bits as they are.
pub(crate) fn le<const N: usize>(values: [f32; N]) -> [u32; N] {
    values.map(|x| x.to_bits().to_le())
}

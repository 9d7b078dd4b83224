//! A document's buffers as kept once its model is decoded: each buffer's bytes, except that
//! buffer 0 may have given back the bytes the pass-through writer need not read from it
//! (`passthrough/unread.rs`): those it replaces, and those the model holds bit for bit
//! (`loaded/from_model.rs`). Whatever reads a buffer after the load (the embedded images, the
//! pass-through writer) reads it here, by its offsets as loaded.

mod from_model;

use std::io::{Read, Write};
use std::ops::Range;

use bytes::Bytes;
use seamlit_mesh::{Model, Object};

pub(crate) use from_model::{Attribute, FromModel};

/// The buffers of a loaded document, addressed by their offsets as loaded.
pub(crate) struct LoadedBuffers {
    buffers: Vec<Bytes>,
    /// Buffer 0's length as loaded.
    host_length: usize,
    /// Where buffer 0 gave some of its bytes back: the ranges it kept (as loaded, in order,
    /// apart), each with where it starts now. `None`: buffer 0 as loaded.
    kept: Option<Vec<(Range<usize>, usize)>>,
    /// The accessors given back whose elements the model holds, in the order of their bytes,
    /// each with the hash of those bytes as loaded.
    from_model: Vec<(FromModel, u64)>,
}

/// Kept bytes start at the offset modulo this that they had: what was aligned stays aligned.
const ALIGN: usize = 16;

impl LoadedBuffers {
    /// The buffers as loaded, nothing given back.
    pub(crate) fn new(buffers: Vec<Bytes>) -> Self {
        let host_length = buffers.first().map_or(0, Bytes::len);
        Self { buffers, host_length, kept: None, from_model: Vec::new() }
    }

    /// Buffer 0 keeps only the bytes of `ranges` (offsets as loaded; they may overlap), moved
    /// together in place so that the rest of its memory is given back; the bytes of
    /// `from_model` (given back too) are written again from the model.
    pub(crate) fn keeping_of_host(
        mut self,
        ranges: Vec<Range<usize>>,
        mut from_model: Vec<FromModel>,
    ) -> Self {
        let Some(host) = self.buffers.first_mut() else { return self };
        from_model.retain(|f| f.bytes.end <= host.len());
        from_model.sort_by_key(|f| f.bytes.start);
        self.from_model = from_model
            .into_iter()
            .map(|f| {
                let hash = f.hash_of(host);
                (f, hash)
            })
            .collect();
        let length = self.host_length;
        let spans = ranges.into_iter().map(|r| r.start.min(length)..r.end.min(length));
        let merged = merged(spans.filter(|r| !r.is_empty()).collect());
        // Nothing else holds the buffer yet (the images are sliced from it after): its
        // allocation is reused, not copied.
        let mut bytes = Vec::from(std::mem::take(host));
        let mut kept = Vec::with_capacity(merged.len());
        let mut at = 0;
        for span in merged {
            // Down, never up: `at` is at most `span.start`, which no earlier span reaches.
            let start = at + (span.start - at) % ALIGN;
            bytes.copy_within(span.clone(), start);
            at = start + span.len();
            kept.push((span, start));
        }
        bytes.truncate(at);
        bytes.shrink_to_fit();
        *host = Bytes::from(bytes);
        self.kept = Some(kept);
        self
    }

    /// How many buffers the document has.
    pub(crate) fn count(&self) -> usize {
        self.buffers.len()
    }

    /// Buffer `buffer`'s length as loaded (0 for none).
    pub(crate) fn len(&self, buffer: usize) -> usize {
        match buffer {
            0 => self.host_length,
            _ => self.buffers.get(buffer).map_or(0, Bytes::len),
        }
    }

    /// The bytes of `range` of buffer `buffer`; `None` past its end, or where buffer 0 gave
    /// some of them back.
    pub(crate) fn get(&self, buffer: usize, range: Range<usize>) -> Option<&[u8]> {
        let bytes = self.buffers.get(buffer)?;
        let range = self.stored(buffer, range)?;
        bytes.get(range)
    }

    /// [`Self::get`] as a shared slice of the buffer (no copy).
    pub(crate) fn slice(&self, buffer: usize, range: Range<usize>) -> Option<Bytes> {
        let bytes = self.buffers.get(buffer)?;
        let range = self.stored(buffer, range)?;
        (range.end <= bytes.len()).then(|| bytes.slice(range))
    }

    /// Where `range` (as loaded) of buffer `buffer` lies now, where it is all kept.
    fn stored(&self, buffer: usize, range: Range<usize>) -> Option<Range<usize>> {
        if range.is_empty() {
            return (range.start <= self.len(buffer)).then_some(0..0);
        }
        let Some(kept) = self.kept.as_ref().filter(|_| buffer == 0) else {
            return Some(range);
        };
        let (span, start) =
            kept.iter().find(|(span, _)| span.start <= range.start && range.end <= span.end)?;
        Some(start + (range.start - span.start)..start + (range.end - span.start))
    }

    /// Writes `range` of buffer 0 (as loaded) to `out`: its bytes; where they were given
    /// back, `model`'s elements they were, else zeros (bytes only replaced data used: see
    /// `passthrough/unread.rs`); zeros past its end.
    pub(crate) fn write_host(
        &self,
        range: Range<usize>,
        model: &Model,
        out: &mut dyn Write,
    ) -> std::io::Result<()> {
        let host = self.buffers.first().map_or(&[][..], |b| &b[..]);
        let whole = [(0..host.len(), 0)];
        let kept = self.kept.as_deref().unwrap_or(&whole);
        let mut at = range.start;
        for (span, start) in kept {
            let (from, to) = (span.start.max(at), span.end.min(range.end));
            if from >= to {
                continue;
            }
            self.write_given_back(at..from, model, out)?;
            out.write_all(&host[start + (from - span.start)..start + (to - span.start)])?;
            at = to;
        }
        self.write_given_back(at..range.end.max(at), model, out)
    }

    /// Writes `range` of buffer 0, given back: the model's elements where they were its
    /// accessors', zeros elsewhere.
    fn write_given_back(
        &self,
        range: Range<usize>,
        model: &Model,
        out: &mut dyn Write,
    ) -> std::io::Result<()> {
        let mut at = range.start;
        for (f, _) in &self.from_model {
            let (from, to) = (f.bytes.start.max(at), f.bytes.end.min(range.end));
            if from >= to {
                continue;
            }
            zeros(out, from - at)?;
            match f.objects.first().and_then(|&o| model.objects.get(o)) {
                Some(object) => f.write(object, from..to, out)?,
                None => zeros(out, to - from)?,
            }
            at = to;
        }
        zeros(out, range.end - at)
    }

    /// Where the model's elements stand in for given-back bytes: whether they are still the
    /// bytes they replace (hashes equal), for every object that holds them; else why not.
    pub(crate) fn check_model(&self, model: &Model) -> Result<(), String> {
        for (f, hash) in &self.from_model {
            for &o in &f.objects {
                let object = model.objects.get(o).ok_or("an object is missing")?;
                if f.hash_in(object) != Some(*hash) {
                    let what = match f.attribute {
                        Attribute::Positions => "positions",
                        Attribute::Uvs => "texture coordinates",
                    };
                    return Err(format!(
                        "object {:?}'s {what} are not those of accessor {} as loaded, whose bytes were not kept",
                        object.name, f.accessor
                    ));
                }
            }
        }
        Ok(())
    }

    /// The elements of accessor `accessor` as the file's bytes, from `object`, and their
    /// size, where its bytes were given back for the model's.
    pub(crate) fn model_elements(
        &self,
        accessor: usize,
        object: &Object,
    ) -> Option<(Vec<u8>, usize)> {
        let (f, _) = self.from_model.iter().find(|(f, _)| f.accessor == accessor)?;
        Some((f.bytes_in(object)?, f.attribute.element_size()))
    }

    /// Buffer `buffer` as stored now (offsets as loaded only where nothing was given back).
    #[cfg(test)]
    pub(crate) fn stored_bytes(&self, buffer: usize) -> &Bytes {
        &self.buffers[buffer]
    }
}

/// `spans` in order, merged where they overlap or touch.
pub(crate) fn merged(mut spans: Vec<Range<usize>>) -> Vec<Range<usize>> {
    spans.sort_by_key(|r| (r.start, r.end));
    let mut merged: Vec<Range<usize>> = Vec::new();
    for span in spans {
        match merged.last_mut() {
            Some(last) if span.start <= last.end => last.end = last.end.max(span.end),
            _ => merged.push(span),
        }
    }
    merged
}

/// Writes `n` zero bytes.
pub(crate) fn zeros(out: &mut dyn Write, n: usize) -> std::io::Result<()> {
    std::io::copy(&mut std::io::repeat(0).take(n as u64), out).map(|_| ())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn loaded(ranges: Vec<Range<usize>>) -> LoadedBuffers {
        let host: Vec<u8> = (0..=255).cycle().take(1000).collect();
        LoadedBuffers::new(vec![Bytes::from(host), Bytes::from_static(b"other")])
            .keeping_of_host(ranges, Vec::new())
    }

    /// Kept ranges read as they were loaded, at any offset inside them; given-back ones and
    /// ranges across a gap read as nothing; other buffers are untouched.
    #[test]
    fn kept_ranges_read_as_loaded() {
        let buffers = loaded(vec![100..200, 150..260, 700..710, 990..2000]);
        let expected =
            |r: Range<usize>| r.map(|i| u8::try_from(i % 256).unwrap()).collect::<Vec<u8>>();
        for range in [100..260, 120..121, 700..710, 990..1000, 255..260] {
            assert_eq!(buffers.get(0, range.clone()), Some(&expected(range.clone())[..]));
            assert_eq!(&buffers.slice(0, range.clone()).unwrap()[..], &expected(range)[..]);
        }
        for range in [99..101, 259..261, 300..400, 705..720, 0..1000] {
            assert_eq!(buffers.get(0, range.clone()), None, "{range:?}");
        }
        assert_eq!(buffers.len(0), 1000);
        assert_eq!(buffers.get(1, 0..5), Some(&b"other"[..]));
        assert!(buffers.stored_bytes(0).len() < 200 + ALIGN * 3, "the rest given back");
    }

    /// Kept bytes keep their offset modulo [`ALIGN`].
    #[test]
    fn kept_bytes_stay_aligned() {
        let buffers = loaded(vec![36..40, 100..104, 517..600]);
        let base = buffers.stored_bytes(0).as_ptr() as usize;
        for (range, _) in buffers.kept.as_ref().unwrap() {
            let at = buffers.slice(0, range.clone()).unwrap().as_ptr() as usize - base;
            assert_eq!(at % ALIGN, range.start % ALIGN, "{range:?}");
        }
    }

    /// The writer's copy of buffer 0: kept bytes as loaded, zeros for the rest and past the end.
    #[test]
    fn written_host_has_zeros_where_bytes_were_given_back() {
        let buffers = loaded(vec![10..20, 30..40]);
        let mut out = Vec::new();
        buffers.write_host(5..1010, &Model::default(), &mut out).unwrap();
        assert_eq!(out.len(), 1005);
        for (i, &b) in out.iter().enumerate() {
            let at = i + 5;
            let kept = (10..20).contains(&at) || (30..40).contains(&at);
            assert_eq!(b, if kept { u8::try_from(at % 256).unwrap() } else { 0 }, "byte {at}");
        }
        let whole = LoadedBuffers::new(vec![Bytes::from_static(b"abc")]);
        let mut out = Vec::new();
        whole.write_host(0..5, &Model::default(), &mut out).unwrap();
        assert_eq!(out, b"abc\0\0");
    }
}

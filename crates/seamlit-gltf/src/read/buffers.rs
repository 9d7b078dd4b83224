//! Where a document's bytes come from: its buffers (the GLB `BIN` chunk, `data:` URIs,
//! files beside the model, meshopt fallback buffers made for the decoder), checked against
//! their declared lengths, the buffer views checked against their buffers, and its images
//! as textures (nothing decoded here).

use super::Reader;
use crate::loaded::LoadedBuffers;
use crate::uri::{Resolved, resolve};
use seamlit_asset::error::IoError;
use seamlit_asset::error::gltf::GltfKind;
use seamlit_asset::{Texture, TextureSource};

impl Reader<'_> {
    pub(super) fn buffers(
        &self,
        document: &gltf::Document,
        json: &serde_json::Value,
        mut blob: Option<Vec<u8>>,
    ) -> Result<Vec<Vec<u8>>, IoError> {
        let mut buffers = Vec::with_capacity(document.buffers().len());
        for buffer in document.buffers() {
            let what = format!("buffer {}", buffer.index());
            // Filled by `decode::meshopt::decode_meshopt`.
            let limit = self.options.max_file_bytes;
            if let Some(length) =
                crate::decode::meshopt::fallback_length(json, buffer.index(), limit, self.path)?
            {
                buffers.push(vec![0; length]);
                continue;
            }
            let data = match buffer.source() {
                gltf::buffer::Source::Bin => match blob.take() {
                    Some(blob) => blob,
                    // No uri and not the BIN chunk: no data (see `lenient.rs`).
                    None => {
                        buffers.push(Vec::new());
                        continue;
                    }
                },
                gltf::buffer::Source::Uri(uri) => {
                    match resolve(self.path, uri, &what, &self.options.files)? {
                        Resolved::Data(bytes, _) => bytes,
                        Resolved::File { file, real } => {
                            match seamlit_asset::files::read_bytes(
                                real.as_deref().unwrap_or(&file),
                                self.options,
                            ) {
                                Err(IoError::Io { source, .. })
                                    if source.kind() == std::io::ErrorKind::NotFound =>
                                {
                                    return Err(IoError::MissingFile {
                                        path: self.path.to_path_buf(),
                                        what,
                                        missing: file,
                                        line: None,
                                    });
                                }
                                other => other?,
                            }
                        }
                    }
                }
            };
            if (data.len() as u64) < buffer.length() as u64 {
                return Err(IoError::gltf_data(
                    self.path.to_path_buf(),
                    GltfKind::BufferLength {
                        buffer: buffer.index(),
                        expected: buffer.length() as u64,
                        actual: data.len() as u64,
                    },
                ));
            }
            buffers.push(data);
        }
        Ok(buffers)
    }

    /// Every buffer view must lie inside its buffer (but those of buffers `without_data`,
    /// which no primitive reads).
    pub(super) fn check_views(
        &self,
        document: &gltf::Document,
        buffers: &[Vec<u8>],
        without_data: &[usize],
    ) -> Result<(), IoError> {
        for view in document.views().filter(|v| !without_data.contains(&v.buffer().index())) {
            let end = (view.offset() as u64).saturating_add(view.length() as u64);
            let available = buffers.get(view.buffer().index()).map_or(0, Vec::len) as u64;
            if end > available {
                return Err(IoError::Gltf {
                    path: self.path.to_path_buf(),
                    place: format!("bufferViews[{}]", view.index()),
                    kind: GltfKind::ViewOutsideBuffer {
                        end,
                        buffer: view.buffer().index(),
                        available,
                    },
                });
            }
        }
        Ok(())
    }
}

impl Reader<'_> {
    /// The images, as textures; `data:` and buffer-view images are embedded bytes, files are
    /// resolved (and refused if they leave the model's folder). Nothing is decoded here.
    pub(super) fn images(
        &self,
        document: &gltf::Document,
        buffers: &LoadedBuffers,
    ) -> Result<Vec<Texture>, IoError> {
        document
            .images()
            .map(|image| {
                let what = format!("image {}", image.index());
                let fallback = || image.name().map_or_else(|| what.clone(), str::to_owned);
                let (name, source) = match image.source() {
                    gltf::image::Source::View { view, mime_type } => {
                        let start = view.offset();
                        // A slice of the buffer (checked against it by `check_views`).
                        let bytes = start
                            .checked_add(view.length())
                            .and_then(|end| buffers.slice(view.buffer().index(), start..end))
                            .unwrap_or_default();
                        let source =
                            TextureSource::Embedded { mime_type: mime_type.to_owned(), bytes };
                        (fallback(), source)
                    }
                    gltf::image::Source::Uri { uri, mime_type } => {
                        match resolve(self.path, uri, &what, &self.options.files)? {
                            Resolved::Data(bytes, declared) => {
                                let mime_type = mime_type.map_or(declared, str::to_owned);
                                (
                                    fallback(),
                                    TextureSource::Embedded { mime_type, bytes: bytes.into() },
                                )
                            }
                            Resolved::File { file, .. } => {
                                let name = image.name().map(str::to_owned).unwrap_or_else(|| {
                                    file.file_name().map_or_else(
                                        || uri.to_owned(),
                                        |n| n.to_string_lossy().into_owned(),
                                    )
                                });
                                (name, TextureSource::File(file))
                            }
                        }
                    }
                };
                Ok(Texture { name, source, image: None })
            })
            .collect()
    }
}

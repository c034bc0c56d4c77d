//! The file-access policy for files an SVG references (`<image href>`, `<feImage href>`):
//! inside the SVG's folder or an allowed folder, regular files, bounded in size; data URIs
//! always (a gzip-compressed SVG in one is bounded like a `.svgz`). See [`crate::Policy`].

use std::path::Path;
use std::sync::{Arc, Mutex};

use usvg::ImageHrefResolver;

use crate::Policy;

/// The references refused so far: (href, why).
pub(crate) type Refused = Arc<Mutex<Vec<(String, String)>>>;

/// usvg's image resolver under `policy`: refused references are recorded in `refused`
/// (and the element dropped); allowed ones are read by usvg's own resolver.
pub(crate) fn resolver(
    dir: Option<&Path>,
    policy: &Policy,
    refused: Refused,
) -> ImageHrefResolver<'static> {
    let dir = dir.map(Path::to_path_buf);
    let allowed = policy.allowed_dirs.clone();
    let max_bytes = policy.max_file_bytes;
    let max_svgz = policy.max_svgz_bytes;
    let max_pixels = policy.max_image_pixels;
    let refused_data = refused.clone();
    let refused_string = refused.clone();
    let default_string = ImageHrefResolver::default_string_resolver();
    let default_data = ImageHrefResolver::default_data_resolver();
    ImageHrefResolver {
        resolve_string: Box::new(move |href: &str, opts: &usvg::Options| {
            let refs = gmotion::input::References {
                owner: "SVG",
                dir: dir.as_deref(),
                allowed: &allowed,
                max_bytes,
            };
            match refs.check(href) {
                Ok(real) => screened(
                    default_string(&real.to_string_lossy(), opts),
                    max_pixels,
                    href,
                    &refused_string,
                ),
                Err(why) => {
                    refused
                        .lock()
                        .unwrap_or_else(|e| e.into_inner())
                        .push((href.to_string(), why));
                    None
                }
            }
        }),
        resolve_data: Box::new(
            move |mime: &str, data: Arc<Vec<u8>>, opts: &usvg::Options| {
                if data.starts_with(&[0x1f, 0x8b]) {
                    match crate::gunzip(&data, max_svgz) {
                        Ok(plain) => {
                            return screened(
                                default_data(mime, Arc::new(plain), opts),
                                max_pixels,
                                "data:",
                                &refused_data,
                            );
                        }
                        Err(why) => {
                            refused_data
                                .lock()
                                .unwrap_or_else(|e| e.into_inner())
                                .push(("data:".to_string(), why));
                            return None;
                        }
                    }
                }
                screened(
                    default_data(mime, data, opts),
                    max_pixels,
                    "data:",
                    &refused_data,
                )
            },
        ),
    }
}

/// `image` unless its header declares more than `max_pixels` pixels, no pixels, or
/// proportions past 65 536 : 1, which are refused (recorded in `refused` under `href`)
/// before usvg places them: decoding would allocate every declared pixel, and usvg panics
/// placing an image so thin that its fitted side rounds to nothing (found by fuzzing: a
/// PNG header declaring 1 207 959 553 × 1 px).
fn screened(
    image: Option<usvg::ImageKind>,
    max_pixels: u64,
    href: &str,
    refused: &Refused,
) -> Option<usvg::ImageKind> {
    let data = match &image {
        Some(
            usvg::ImageKind::PNG(d)
            | usvg::ImageKind::JPEG(d)
            | usvg::ImageKind::GIF(d)
            | usvg::ImageKind::WEBP(d),
        ) => d,
        _ => return image,
    };
    let Some((w, h)) = gmotion::scene::image_pixel_size(data) else {
        return image;
    };
    let why = if w == 0 || h == 0 || w.max(h) / w.min(h) > 65_536 {
        format!("it declares {w} × {h} pixels, proportions no renderer places")
    } else if w.saturating_mul(h) > max_pixels {
        format!(
            "it declares {w} × {h} pixels, more than the limit of {max_pixels} (raise it with --limit image-pixels=N)"
        )
    } else {
        return image;
    };
    refused
        .lock()
        .unwrap_or_else(|e| e.into_inner())
        .push((href.to_string(), why));
    None
}

//! Raster images: an image layer (`ty: 2`) drawing an image asset embedded as a `data:`
//! URL, placed by the image's whole transform.
//!
//! A Lottie layer transform has no skew, so a skewed placement becomes two levels: the
//! outer on a null layer the image layer is parented to (a null draws nothing and its
//! opacity is not inherited, so the image keeps its own).

use std::hash::{DefaultHasher, Hash, Hasher};

use super::*;
use crate::model::ImageAsset;
use gmotion::scene::{ImageFormat, ImageNode};

impl Builder<'_> {
    pub(super) fn image(&mut self, i: &ImageNode, acc: Affine, env: Env, comp: &mut Comp) {
        if env.alpha <= 0.0 || i.width <= 0.0 || i.height <= 0.0 {
            return;
        }
        // Lottie sizes an image asset in whole pixels; the layer scales it back to the
        // image's own size.
        let w = i.width.round().max(1.0);
        let h = i.height.round().max(1.0);
        let id = asset_name(i, (w as u32, h as u32));
        if !self.assets.iter().any(|a| a.id == id) {
            if matches!(i.format, ImageFormat::Gif | ImageFormat::Webp) {
                self.warnings.push(format!(
                    "{}: {} image embedded as it is: lottie-web draws it in browsers that decode {0}, rlottie and ThorVG draw only PNG and JPEG",
                    describe(i),
                    i.format.mime()
                ));
            }
            self.assets.push(Asset {
                id: id.clone(),
                layers: Vec::new(),
                image: Some(ImageAsset {
                    w: w as u32,
                    h: h as u32,
                    p: i.data_url(),
                }),
            });
        }
        if !i.smooth {
            self.warnings.push(format!(
                "{}: image-rendering ignored (Lottie players always smooth images)",
                describe(i)
            ));
        }
        let m = acc * Affine::scale_non_uniform(i.width / w, i.height / h);
        let mut levels = decompose(m, Point::ORIGIN);
        let inner = levels.pop().expect("decompose gives at least one level");
        let mut layers = Vec::with_capacity(2);
        let mut l = comp.layer(LayerKind::Image, name(i), self.src.op);
        l.ref_id = Some(id);
        l.ks = full_transform(static_level(&inner));
        if env.alpha < 1.0 {
            l.ks.o = Some(Prop::scalar(N::coord(env.alpha * 100.0)));
        }
        if let Some(outer) = levels.pop() {
            let mut null = comp.layer(LayerKind::Null, format!("{}/place", l.nm), self.src.op);
            null.ks = full_transform(static_level(&outer));
            l.parent = Some(null.ind);
            layers.push(l);
            layers.push(null);
        } else {
            layers.push(l);
        }
        comp.items.push(Item::Layers(layers));
    }
}

/// The layer's name: the element's id, or `image`.
fn name(i: &ImageNode) -> String {
    if i.id.is_empty() {
        "image".to_string()
    } else {
        i.id.clone()
    }
}

/// The image as a warning names it.
fn describe(i: &ImageNode) -> String {
    if i.id.is_empty() {
        "<image>".to_string()
    } else {
        format!("<image id=\"{}\">", i.id)
    }
}

/// An image asset's id, from its content and size: the same picture drawn many times (a
/// Figma image fill repeated, a pattern's tiles) is embedded once.
fn asset_name(i: &ImageNode, size: (u32, u32)) -> String {
    let mut h = DefaultHasher::new();
    i.data.hash(&mut h);
    size.hash(&mut h);
    format!("image_{:016x}", h.finish())
}

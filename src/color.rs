//! Colours: straight (non-premultiplied) sRGB with alpha, components in `0..=1`.

/// An sRGB colour with straight alpha; every component lies in `0..=1`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Color {
    /// Red.
    pub r: f32,
    /// Green.
    pub g: f32,
    /// Blue.
    pub b: f32,
    /// Alpha (1 = opaque).
    pub a: f32,
}

impl Color {
    /// Opaque black.
    pub const BLACK: Color = Color::rgb(0.0, 0.0, 0.0);
    /// Opaque white.
    pub const WHITE: Color = Color::rgb(1.0, 1.0, 1.0);

    /// An opaque colour from components in `0..=1`.
    pub const fn rgb(r: f32, g: f32, b: f32) -> Color {
        Color { r, g, b, a: 1.0 }
    }

    /// An opaque colour from 8-bit components.
    pub fn rgb8(r: u8, g: u8, b: u8) -> Color {
        Color::rgb(r as f32 / 255.0, g as f32 / 255.0, b as f32 / 255.0)
    }

    /// Component-wise linear interpolation (in sRGB space, as SVG and Lottie players do).
    pub fn lerp(self, other: Color, t: f32) -> Color {
        Color {
            r: self.r + (other.r - self.r) * t,
            g: self.g + (other.g - self.g) * t,
            b: self.b + (other.b - self.b) * t,
            a: self.a + (other.a - self.a) * t,
        }
    }

    /// The 8-bit components, rounded and clamped.
    pub fn to_rgba8(self) -> [u8; 4] {
        let q = |v: f32| (v.clamp(0.0, 1.0) * 255.0).round() as u8;
        [q(self.r), q(self.g), q(self.b), q(self.a)]
    }

    /// `#rrggbb` (alpha is written separately as an opacity by SVG writers).
    pub fn to_hex(self) -> String {
        let [r, g, b, _] = self.to_rgba8();
        format!("#{r:02x}{g:02x}{b:02x}")
    }

    /// Parses `#rgb`, `#rrggbb`, `#rrggbbaa` or a CSS colour keyword.
    pub fn parse(s: &str) -> Option<Color> {
        let s = s.trim();
        if let Some(hex) = s.strip_prefix('#') {
            let digit = |i: usize| u8::from_str_radix(hex.get(i..i + 1)?, 16).ok();
            let byte = |i: usize| u8::from_str_radix(hex.get(i..i + 2)?, 16).ok();
            return match hex.len() {
                3 => Some(Color::rgb8(digit(0)? * 17, digit(1)? * 17, digit(2)? * 17)),
                6 => Some(Color::rgb8(byte(0)?, byte(2)?, byte(4)?)),
                8 => {
                    let mut c = Color::rgb8(byte(0)?, byte(2)?, byte(4)?);
                    c.a = byte(6)? as f32 / 255.0;
                    Some(c)
                }
                _ => None,
            };
        }
        if !s.chars().all(|c| c.is_ascii_alphabetic()) {
            return None;
        }
        // svgtypes is usvg's own parser, so the keyword list is the one renderers use.
        let c: svgtypes::Color = s.parse().ok()?;
        Some(Color::rgb8(c.red, c.green, c.blue))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_hex_and_keywords() {
        assert_eq!(Color::parse("#f00"), Some(Color::rgb(1.0, 0.0, 0.0)));
        assert_eq!(Color::parse("#00ff00").unwrap().to_hex(), "#00ff00");
        assert_eq!(Color::parse("steelblue").unwrap().to_hex(), "#4682b4");
        assert_eq!(Color::parse("#12"), None);
        assert_eq!(Color::parse("notacolour"), None);
    }
}

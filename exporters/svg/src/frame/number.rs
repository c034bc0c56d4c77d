//! Numbers and colours as SVG text.
//!
//! Every number goes out at `f32` precision, the precision usvg and resvg compute in: the
//! shortest text that reads back to the same `f32`, so output is exact for the renderer,
//! short, and identical byte for byte on every run.

use std::fmt::Write;

use kurbo::{Affine, Point};

use gmotion::color::Color;

/// Appends `v` as the shortest decimal that reads back as the same `f32`; `0` for zero
/// (and for non-finite values, which SVG cannot carry).
pub(super) fn num(out: &mut String, v: f64) {
    let f = v as f32;
    if f == 0.0 || !f.is_finite() {
        out.push('0');
        return;
    }
    let a = f.abs();
    // Plain notation reads best; exponents keep very small and very large values short.
    if (1e-5..1e9).contains(&a) {
        // zmij prints the shortest digits here in plain notation as `{f}` does, whole
        // numbers with a `.0` added, four times faster (a large document's writing spent a
        // third of its time in std's float formatting). Checked on every `f32` in this
        // range: the texts differ only where two shortest texts are equally near (std
        // rounds the tie up, zmij to even); both read back as `f`.
        let mut buf = zmij::Buffer::new();
        let text = buf.format_finite(f);
        out.push_str(text.strip_suffix(".0").unwrap_or(text));
    } else {
        let _ = write!(out, "{f:e}");
    }
}

/// Appends `x y`.
pub(super) fn point(out: &mut String, p: Point) {
    num(out, p.x);
    out.push(' ');
    num(out, p.y);
}

/// Appends ` name="v"`.
pub(super) fn attr_num(out: &mut String, name: &str, v: f64) {
    out.push(' ');
    out.push_str(name);
    out.push_str("=\"");
    num(out, v);
    out.push('"');
}

/// Appends ` name="matrix(…)"` unless `ts` is the identity.
pub(super) fn attr_transform(out: &mut String, name: &str, ts: Affine) {
    if ts == Affine::IDENTITY {
        return;
    }
    let [a, b, c, d, e, f] = ts.as_coeffs();
    out.push(' ');
    out.push_str(name);
    if [a, b, c, d] == [1.0, 0.0, 0.0, 1.0] {
        out.push_str("=\"translate(");
        num(out, e);
        out.push(' ');
        num(out, f);
    } else {
        out.push_str("=\"matrix(");
        for (i, v) in [a, b, c, d, e, f].into_iter().enumerate() {
            if i > 0 {
                out.push(' ');
            }
            num(out, v);
        }
    }
    out.push_str(")\"");
}

/// Appends `#rrggbb`.
pub(super) fn hex(out: &mut String, c: Color) {
    const DIGITS: &[u8; 16] = b"0123456789abcdef";
    out.push('#');
    for v in &c.to_rgba8()[..3] {
        out.push(DIGITS[(v >> 4) as usize] as char);
        out.push(DIGITS[(v & 15) as usize] as char);
    }
}

/// Appends `s` escaped for an XML attribute value.
pub(super) fn escaped(out: &mut String, s: &str) {
    for ch in s.chars() {
        match ch {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            _ => out.push(ch),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn n(v: f64) -> String {
        let mut s = String::new();
        num(&mut s, v);
        s
    }

    #[test]
    fn numbers_are_short_and_exact_in_f32() {
        assert_eq!(n(100.0), "100");
        assert_eq!(n(-0.0), "0");
        assert_eq!(n(0.1 + 0.2), "0.3");
        assert_eq!(n(6.123233995736766e-17), "6.123234e-17");
        assert_eq!(n(f64::NAN), "0");
        for v in [1.0 / 3.0, 12345.678, -0.000123, 2.5e10] {
            assert_eq!(n(v).parse::<f32>().unwrap(), v as f32);
        }
    }

    /// Spread over the plain-notation range: each text reads back as the same `f32`, and
    /// is std's shortest text or, in a tie, one of the same length.
    #[test]
    fn plain_numbers_are_the_shortest_texts_that_read_back() {
        let (lo, hi) = (1e-5f32.to_bits(), 1e9f32.to_bits());
        let mut ties = 0;
        for k in 0..200_000u32 {
            let f = f32::from_bits(lo + (k as u64 * u64::from(hi - lo) / 200_000) as u32);
            for v in [f, -f] {
                let text = n(f64::from(v));
                let std = format!("{v}");
                assert_eq!(text.parse::<f32>().unwrap(), v, "{std}");
                if text != std {
                    assert_eq!(text.len(), std.len(), "{text} for {std}");
                    ties += 1;
                }
            }
        }
        // Ties are about one value in a hundred.
        assert!(ties < 20_000, "{ties}");
    }

    #[test]
    fn transforms_and_colours() {
        let mut s = String::new();
        attr_transform(&mut s, "transform", Affine::translate((2.0, -3.5)));
        attr_transform(&mut s, "transform", Affine::IDENTITY);
        assert_eq!(s, " transform=\"translate(2 -3.5)\"");
        s.clear();
        hex(&mut s, Color::rgb8(255, 8, 160));
        assert_eq!(s, "#ff08a0");
        s.clear();
        escaped(&mut s, "a<\"&");
        assert_eq!(s, "a&lt;&quot;&amp;");
    }
}

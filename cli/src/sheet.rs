//! `gmotion variations`' contact sheet: frames in a grid, each with its seed written
//! under it in a small built-in pixel font (the renderer loads no fonts).

use resvg::tiny_skia::{Color, Paint, Pixmap, PixmapPaint, Rect, Transform};

/// Pixels per font dot.
const DOT: u32 = 3;
/// The band under each frame that holds its label.
const BAND: u32 = 7 * DOT;

/// Rows of a 3 × 5 dot digit, top first, high bit on the left.
const DIGITS: [[u8; 5]; 10] = [
    [7, 5, 5, 5, 7],
    [2, 6, 2, 2, 7],
    [7, 1, 7, 4, 7],
    [7, 1, 7, 1, 7],
    [5, 5, 7, 1, 1],
    [7, 4, 7, 1, 7],
    [7, 4, 7, 5, 7],
    [7, 1, 1, 1, 1],
    [7, 5, 7, 5, 7],
    [7, 5, 7, 1, 7],
];

/// Draws `n` in dark grey with its top-left corner at (`x`, `y`).
fn draw_number(sheet: &mut Pixmap, n: u64, x: u32, y: u32) {
    let mut paint = Paint::default();
    paint.set_color(Color::from_rgba8(40, 40, 40, 255));
    for (i, ch) in n.to_string().bytes().enumerate() {
        let glyph = DIGITS[usize::from(ch - b'0')];
        let gx = x + i as u32 * 4 * DOT;
        for (row, bits) in glyph.iter().enumerate() {
            for col in 0..3 {
                if bits & (4 >> col) != 0
                    && let Some(r) = Rect::from_xywh(
                        (gx + col * DOT) as f32,
                        (y + row as u32 * DOT) as f32,
                        DOT as f32,
                        DOT as f32,
                    )
                {
                    sheet.fill_rect(r, &paint, Transform::identity(), None);
                }
            }
        }
    }
}

/// The frames (all one size) in a near-square grid on white, each labelled with its seed;
/// `None` when the sheet would be empty or too large to allocate.
pub fn contact_sheet(frames: &[(u64, Pixmap)]) -> Option<Pixmap> {
    let (w, h) = frames.first().map(|(_, p)| (p.width(), p.height()))?;
    let n = frames.len() as u32;
    let cols = (f64::from(n).sqrt().ceil() as u32).max(1);
    let rows = n.div_ceil(cols);
    let gap = 2 * DOT;
    let cell_w = w + gap;
    let cell_h = h + BAND + gap;
    let mut sheet = Pixmap::new(cols * cell_w + gap, rows * cell_h + gap)?;
    sheet.fill(Color::WHITE);
    for (i, (seed, frame)) in frames.iter().enumerate() {
        let (c, r) = (i as u32 % cols, i as u32 / cols);
        let (x, y) = (gap + c * cell_w, gap + r * cell_h);
        sheet.draw_pixmap(
            x as i32,
            y as i32,
            frame.as_ref(),
            &PixmapPaint::default(),
            Transform::identity(),
            None,
        );
        draw_number(&mut sheet, *seed, x, y + h + DOT);
    }
    Some(sheet)
}

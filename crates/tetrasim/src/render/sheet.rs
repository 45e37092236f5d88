//! Composing rendered frames: captions on a frame, a row of methods side by side (one frame
//! of the animation), and the contact sheet (one row per method, one column per sampled
//! frame: the paper's Fig. 11 in one picture).

use super::image::Image;
use super::style::{BACKGROUND_RGB, TEXT_RGB};
use super::text;

/// Text scale for an image `height` pixels tall.
fn scale_for(height: u32) -> u32 {
    if height >= 160 {
        2
    } else {
        1
    }
}

/// Writes `lines` at the top-left corner of `image`, one under the other (the sky is
/// there, so they do not cover the object).
pub fn caption(image: &mut Image, lines: &[&str]) {
    let s = scale_for(image.height);
    let pad = i64::from(3 * s + 2);
    let step = i64::from(text::height(s) + 3 * s);
    for (k, line) in lines.iter().enumerate() {
        text::draw(image, pad, pad + k as i64 * step, line, s, TEXT_RGB);
    }
}

/// The images side by side (all of the first one's height), left to right.
pub fn row(images: &[Image]) -> Image {
    let height = images.first().map(|i| i.height).unwrap_or(1);
    let width = images.iter().map(|i| i.width).sum::<u32>().max(1);
    let mut out = Image::filled(width, height, BACKGROUND_RGB);
    let mut x = 0;
    for image in images {
        out.blit(image, x, 0);
        x += image.width;
    }
    out
}

/// A contact sheet: `cells[row][column]` (all one size), a header line per column and a
/// label (one or more lines) per row, thin gaps between cells.
pub fn contact_sheet(cells: &[Vec<Image>], columns: &[String], rows: &[Vec<String>]) -> Image {
    let (cw, ch) = cells
        .first()
        .and_then(|r| r.first())
        .map(|i| (i.width, i.height))
        .unwrap_or((1, 1));
    let s = if ch >= 150 { 2 } else { 1 };
    let line = text::height(s) + 4 * s;
    let gap = 2 * s;
    let label_w = rows
        .iter()
        .flatten()
        .map(|l| text::width(l, s))
        .max()
        .unwrap_or(0)
        + 6 * s;
    let ncols = cells.iter().map(Vec::len).max().unwrap_or(0) as u32;
    let nrows = cells.len() as u32;
    let width = label_w + ncols * (cw + gap);
    let header = line + 2 * s;
    let height = header + nrows * (ch + gap);
    let mut out = Image::filled(width.max(1), height.max(1), [255, 255, 255]);
    for (c, title) in columns.iter().enumerate().take(ncols as usize) {
        let x = label_w + c as u32 * (cw + gap) + (cw.saturating_sub(text::width(title, s))) / 2;
        text::draw(&mut out, i64::from(x), i64::from(2 * s), title, s, TEXT_RGB);
    }
    for (r, cells_of_row) in cells.iter().enumerate() {
        let y = header + r as u32 * (ch + gap);
        let lines = rows.get(r).map(Vec::as_slice).unwrap_or(&[]);
        let block = lines.len() as u32 * line;
        for (k, l) in lines.iter().enumerate() {
            let ty = y + ch.saturating_sub(block) / 2 + k as u32 * line;
            text::draw(&mut out, i64::from(3 * s), i64::from(ty), l, s, TEXT_RGB);
        }
        for (c, cell) in cells_of_row.iter().enumerate() {
            out.blit(cell, label_w + c as u32 * (cw + gap), y);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_sheet_puts_each_cell_in_its_row_and_column() {
        let colours = [[[255, 0, 0], [0, 255, 0]], [[0, 0, 255], [255, 255, 0]]];
        let cells: Vec<Vec<Image>> = colours
            .iter()
            .map(|r| r.iter().map(|&c| Image::filled(40, 30, c)).collect())
            .collect();
        let sheet = contact_sheet(
            &cells,
            &["t = 0".into(), "t = 1".into()],
            &[vec!["mss".into()], vec!["volume".into()]],
        );
        // 1-pixel text scale for 30-pixel cells: gaps of 2 pixels.
        let label_w = sheet.width - 2 * (40 + 2);
        let header = sheet.height - 2 * (30 + 2);
        for (r, row) in colours.iter().enumerate() {
            for (c, colour) in row.iter().enumerate() {
                let x = label_w + c as u32 * 42 + 20;
                let y = header + r as u32 * 32 + 15;
                assert_eq!(sheet.pixel(x, y), Some(*colour), "cell {r},{c}");
            }
        }
        // Labels were written in the left column and the header.
        let dark = |x0: u32, x1: u32, y0: u32, y1: u32| {
            (y0..y1).any(|y| (x0..x1).any(|x| sheet.pixel(x, y) == Some(TEXT_RGB)))
        };
        assert!(dark(0, label_w, header, sheet.height));
        assert!(dark(label_w, sheet.width, 0, header));
    }

    #[test]
    fn row_places_images_left_to_right() {
        let r = row(&[
            Image::filled(3, 2, [1, 1, 1]),
            Image::filled(5, 2, [9, 9, 9]),
        ]);
        assert_eq!((r.width, r.height), (8, 2));
        assert_eq!(r.pixel(2, 1), Some([1, 1, 1]));
        assert_eq!(r.pixel(3, 0), Some([9, 9, 9]));
    }
}

//! CPU images: 8-bit sRGB RGBA pixels as read back from the GPU, composed into sheets and
//! written as PNG or animated GIF (each file written to a temporary name, then renamed).

use std::path::Path;

use crate::error::{Error, Result};
use crate::mesh::io::write_atomic;

/// An RGBA image, 8 bits per channel (sRGB), rows top to bottom.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Image {
    /// Width [pixels].
    pub width: u32,
    /// Height [pixels].
    pub height: u32,
    /// `width * height * 4` bytes, row-major.
    pub rgba: Vec<u8>,
}

impl Image {
    /// An image filled with `rgb` (opaque).
    pub fn filled(width: u32, height: u32, rgb: [u8; 3]) -> Self {
        let rgba = [rgb[0], rgb[1], rgb[2], 255]
            .into_iter()
            .cycle()
            .take(width as usize * height as usize * 4)
            .collect();
        Image {
            width,
            height,
            rgba,
        }
    }

    /// The pixel at column `x`, row `y` (RGB), or `None` outside the image.
    pub fn pixel(&self, x: u32, y: u32) -> Option<[u8; 3]> {
        if x >= self.width || y >= self.height {
            return None;
        }
        let i = 4 * (y as usize * self.width as usize + x as usize);
        Some([self.rgba[i], self.rgba[i + 1], self.rgba[i + 2]])
    }

    /// Sets the pixel at (`x`, `y`) when it is inside the image.
    pub fn set(&mut self, x: i64, y: i64, rgb: [u8; 3]) {
        if x < 0 || y < 0 || x >= i64::from(self.width) || y >= i64::from(self.height) {
            return;
        }
        let i = 4 * (y as usize * self.width as usize + x as usize);
        self.rgba[i..i + 4].copy_from_slice(&[rgb[0], rgb[1], rgb[2], 255]);
    }

    /// Copies `other` with its top-left corner at (`x`, `y`), clipped to this image.
    pub fn blit(&mut self, other: &Image, x: u32, y: u32) {
        let w = other.width.min(self.width.saturating_sub(x)) as usize;
        for row in 0..other.height.min(self.height.saturating_sub(y)) as usize {
            let src = 4 * row * other.width as usize;
            let dst = 4 * ((y as usize + row) * self.width as usize + x as usize);
            self.rgba[dst..dst + 4 * w].copy_from_slice(&other.rgba[src..src + 4 * w]);
        }
    }

    /// The image encoded as an 8-bit RGBA PNG; `compact` trades encoding time (about 6x)
    /// for a third smaller file.
    pub fn png_bytes(&self, compact: bool) -> Result<Vec<u8>> {
        let mut out = Vec::new();
        let mut encoder = png::Encoder::new(&mut out, self.width, self.height);
        encoder.set_color(png::ColorType::Rgba);
        encoder.set_depth(png::BitDepth::Eight);
        encoder.set_source_srgb(png::SrgbRenderingIntent::Perceptual);
        encoder.set_compression(match compact {
            true => png::Compression::Balanced,
            false => png::Compression::Fast,
        });
        let encoded = encoder
            .write_header()
            .and_then(|mut w| w.write_image_data(&self.rgba).and_then(|()| w.finish()));
        encoded.map_err(|e| {
            Error::Gpu(format!(
                "encoding a {}x{} PNG: {e}",
                self.width, self.height
            ))
        })?;
        Ok(out)
    }

    /// Writes the image as PNG to `path` (atomically); see [`Image::png_bytes`] for `compact`.
    pub fn save_png(&self, path: &Path, compact: bool) -> Result<()> {
        let bytes = self.png_bytes(compact)?;
        Ok(write_atomic(path, |w| w.write_all(&bytes))?)
    }
}

/// An animated GIF built in memory frame by frame (each frame gets its own 256-colour
/// palette), written to its file atomically by [`GifWriter::finish`].
pub struct GifWriter {
    encoder: gif::Encoder<Vec<u8>>,
    width: u32,
    height: u32,
    delay_cs: u16,
}

impl GifWriter {
    /// A looping animation of `width` x `height` frames shown `delay_cs` hundredths of a
    /// second each.
    pub fn new(width: u32, height: u32, delay_cs: u16) -> Result<Self> {
        let (w, h) = gif_size(width, height)?;
        let mut encoder = gif::Encoder::new(Vec::new(), w, h, &[])
            .map_err(|e| Error::Gpu(format!("starting a GIF: {e}")))?;
        encoder
            .set_repeat(gif::Repeat::Infinite)
            .map_err(|e| Error::Gpu(format!("starting a GIF: {e}")))?;
        Ok(GifWriter {
            encoder,
            width,
            height,
            delay_cs,
        })
    }

    /// Appends one frame (quantised to 256 colours); it must have the animation's size.
    pub fn push(&mut self, image: &Image) -> Result<()> {
        if (image.width, image.height) != (self.width, self.height) {
            return Err(Error::Gpu(format!(
                "GIF frame of {}x{} in a {}x{} animation",
                image.width, image.height, self.width, self.height
            )));
        }
        let (w, h) = gif_size(self.width, self.height)?;
        let mut rgba = image.rgba.clone();
        let mut frame = gif::Frame::from_rgba_speed(w, h, &mut rgba, 10);
        frame.delay = self.delay_cs;
        self.encoder
            .write_frame(&frame)
            .map_err(|e| Error::Gpu(format!("encoding a GIF frame: {e}")))
    }

    /// Finishes the animation and writes it to `path` (atomically).
    pub fn finish(self, path: &Path) -> Result<()> {
        let bytes = self
            .encoder
            .into_inner()
            .map_err(|e| Error::io(path, std::io::Error::other(e)))?;
        Ok(write_atomic(path, |w| w.write_all(&bytes))?)
    }
}

fn gif_size(width: u32, height: u32) -> Result<(u16, u16)> {
    match (u16::try_from(width), u16::try_from(height)) {
        (Ok(w), Ok(h)) => Ok((w, h)),
        _ => Err(Error::param(
            "gif",
            format!("a GIF is at most 65535 pixels a side; this one is {width}x{height}"),
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn blit_clips_and_png_round_trips() {
        let mut a = Image::filled(4, 3, [10, 20, 30]);
        let b = Image::filled(2, 2, [200, 100, 0]);
        a.blit(&b, 3, 2);
        assert_eq!(a.pixel(3, 2), Some([200, 100, 0]));
        assert_eq!(a.pixel(2, 2), Some([10, 20, 30]));
        assert_eq!(a.pixel(4, 0), None);
        for compact in [false, true] {
            let bytes = a.png_bytes(compact).unwrap();
            let decoder = png::Decoder::new(std::io::Cursor::new(bytes));
            let mut reader = decoder.read_info().unwrap();
            let mut buf = vec![0; reader.output_buffer_size().unwrap()];
            let info = reader.next_frame(&mut buf).unwrap();
            assert_eq!((info.width, info.height), (4, 3));
            assert_eq!(&buf[..info.buffer_size()], &a.rgba[..], "compact {compact}");
        }
    }

    #[test]
    fn gif_keeps_frames_and_rejects_a_wrong_size() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("a.gif");
        let mut gif = GifWriter::new(8, 6, 4).unwrap();
        gif.push(&Image::filled(8, 6, [255, 0, 0])).unwrap();
        gif.push(&Image::filled(8, 6, [0, 0, 255])).unwrap();
        assert!(gif.push(&Image::filled(6, 8, [0, 0, 0])).is_err());
        gif.finish(&path).unwrap();
        let mut decoder = gif::DecodeOptions::new();
        decoder.set_color_output(gif::ColorOutput::RGBA);
        let mut reader = decoder
            .read_info(std::fs::File::open(&path).unwrap())
            .unwrap();
        let mut colours = Vec::new();
        while let Some(frame) = reader.read_next_frame().unwrap() {
            assert_eq!(frame.delay, 4);
            colours.push([frame.buffer[0], frame.buffer[1], frame.buffer[2]]);
        }
        assert_eq!(colours.len(), 2);
        assert!(colours[0][0] > 200 && colours[0][2] < 50, "{colours:?}");
        assert!(colours[1][2] > 200 && colours[1][0] < 50, "{colours:?}");
    }
}

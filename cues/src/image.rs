//! Plain image types at the crate boundary.
//!
//! Callers (the renderer, a policy server, another simulator) exchange frames as bare RGB8
//! buffers, so the public types are plain structs; tiny-skia's premultiplied `Pixmap` stays an
//! implementation detail of the drawing code.

use serde::{Deserialize, Serialize};

/// Why an image buffer was rejected.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum ImageError {
    #[error("image of {width}x{height} with {channels} channels needs {expected} bytes, got {got}")]
    WrongLength { width: u32, height: u32, channels: u32, expected: usize, got: usize },
    #[error("image size {width}x{height} is empty or too large (at most 16384 per side)")]
    BadSize { width: u32, height: u32 },
}

/// Largest side we accept; keeps `width * height * 4` far from overflow.
const MAX_SIDE: u32 = 16384;

fn check(width: u32, height: u32, channels: u32, len: usize) -> Result<(), ImageError> {
    if width == 0 || height == 0 || width > MAX_SIDE || height > MAX_SIDE {
        return Err(ImageError::BadSize { width, height });
    }
    let expected = width as usize * height as usize * channels as usize;
    if len != expected {
        return Err(ImageError::WrongLength { width, height, channels, expected, got: len });
    }
    Ok(())
}

/// Reverses the pixels of every row in place (`channels` bytes a pixel): the bytes of a row
/// reversed, then each pixel's back in order.
fn mirror_rows(data: &mut [u8], width: u32, channels: usize) {
    let row_len = width as usize * channels;
    if row_len == 0 {
        return;
    }
    for row in data.chunks_exact_mut(row_len) {
        row.reverse();
        for px in row.chunks_exact_mut(channels) {
            px.reverse();
        }
    }
}

/// An RGB8 image, row 0 at the top, rows packed without padding.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct RgbImage {
    pub width: u32,
    pub height: u32,
    pub data: Vec<u8>,
}

impl RgbImage {
    /// A black image.
    pub fn new(width: u32, height: u32) -> Result<RgbImage, ImageError> {
        Self::filled(width, height, [0, 0, 0])
    }

    /// An image filled with one colour.
    pub fn filled(width: u32, height: u32, rgb: [u8; 3]) -> Result<RgbImage, ImageError> {
        check(width, height, 3, width as usize * height as usize * 3)?;
        let data = rgb.iter().copied().cycle().take(width as usize * height as usize * 3).collect();
        Ok(RgbImage { width, height, data })
    }

    /// Wraps a buffer after checking its length.
    pub fn from_raw(width: u32, height: u32, data: Vec<u8>) -> Result<RgbImage, ImageError> {
        check(width, height, 3, data.len())?;
        Ok(RgbImage { width, height, data })
    }

    /// Checks that `data` matches the stated size (the fields are public).
    pub fn validate(&self) -> Result<(), ImageError> {
        check(self.width, self.height, 3, self.data.len())
    }

    /// The pixel at (x, y); `None` outside the image.
    pub fn pixel(&self, x: u32, y: u32) -> Option<[u8; 3]> {
        if x >= self.width || y >= self.height {
            return None;
        }
        let i = (y as usize * self.width as usize + x as usize) * 3;
        Some([self.data[i], self.data[i + 1], self.data[i + 2]])
    }

    /// Mirrors the image left–right in place: pixel `(x, y)` goes to `(width − 1 − x, y)`.
    pub fn mirror_left_right(&mut self) {
        mirror_rows(&mut self.data, self.width, 3);
    }
}

/// An RGBA8 image with straight (not premultiplied) alpha, row 0 at the top.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct RgbaImage {
    pub width: u32,
    pub height: u32,
    pub data: Vec<u8>,
}

impl RgbaImage {
    /// A fully transparent image.
    pub fn new(width: u32, height: u32) -> Result<RgbaImage, ImageError> {
        check(width, height, 4, width as usize * height as usize * 4)?;
        Ok(RgbaImage { width, height, data: vec![0; width as usize * height as usize * 4] })
    }

    /// Wraps a buffer after checking its length.
    pub fn from_raw(width: u32, height: u32, data: Vec<u8>) -> Result<RgbaImage, ImageError> {
        check(width, height, 4, data.len())?;
        Ok(RgbaImage { width, height, data })
    }

    /// Checks that `data` matches the stated size (the fields are public).
    pub fn validate(&self) -> Result<(), ImageError> {
        check(self.width, self.height, 4, self.data.len())
    }

    /// The pixel at (x, y); `None` outside the image.
    pub fn pixel(&self, x: u32, y: u32) -> Option<[u8; 4]> {
        if x >= self.width || y >= self.height {
            return None;
        }
        let i = (y as usize * self.width as usize + x as usize) * 4;
        Some([self.data[i], self.data[i + 1], self.data[i + 2], self.data[i + 3]])
    }

    /// Mirrors the image left–right in place: pixel `(x, y)` goes to `(width − 1 − x, y)`.
    pub fn mirror_left_right(&mut self) {
        mirror_rows(&mut self.data, self.width, 4);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mirroring_moves_each_pixel_to_the_other_side_of_its_row() {
        let (w, h) = (5u32, 3u32);
        let rgb: Vec<u8> = (0..w * h * 3).map(|k| k as u8).collect();
        let mut img = RgbImage::from_raw(w, h, rgb.clone()).unwrap();
        img.mirror_left_right();
        let rgba: Vec<u8> = (0..w * h * 4).map(|k| (k * 7) as u8).collect();
        let mut img4 = RgbaImage::from_raw(w, h, rgba.clone()).unwrap();
        img4.mirror_left_right();
        let before3 = RgbImage::from_raw(w, h, rgb).unwrap();
        let before4 = RgbaImage::from_raw(w, h, rgba).unwrap();
        for y in 0..h {
            for x in 0..w {
                assert_eq!(img.pixel(w - 1 - x, y), before3.pixel(x, y));
                assert_eq!(img4.pixel(w - 1 - x, y), before4.pixel(x, y));
            }
        }
        img.mirror_left_right();
        assert_eq!(img, before3);
    }
}

//! Image files: PNG in and out, animated GIFs of rollouts, side-by-side composition.
//!
//! Pure Rust (`image` with only its PNG codec, `gif` with NeuQuant quantisation), so this also
//! works in wasm when given bytes instead of paths.

use std::io::Write;
use std::path::Path;

use thiserror::Error;

use crate::frame::RgbImage;

/// Why an image could not be read or written.
#[derive(Debug, Error)]
pub enum ImageIoError {
    #[error("{context}: {source}")]
    Png { context: String, source: image::ImageError },
    #[error("encoding PNG: {0}")]
    PngText(String),
    #[error("{path}: {source}")]
    Io { path: String, source: std::io::Error },
    #[error("GIF: {0}")]
    Gif(#[from] gif::EncodingError),
    #[error("{0}")]
    Size(String),
}

/// Checks that the image's byte length matches its size (its fields are public).
fn check(img: &RgbImage) -> Result<(), ImageIoError> {
    if img.data.len() != img.width as usize * img.height as usize * 3 {
        return Err(ImageIoError::Size(format!(
            "image claims {}×{} pixels but holds {} bytes (expected {})",
            img.width,
            img.height,
            img.data.len(),
            img.width as usize * img.height as usize * 3
        )));
    }
    Ok(())
}

/// PNG file bytes of an RGB image.
pub fn encode_png(img: &RgbImage) -> Result<Vec<u8>, ImageIoError> {
    encode_png_with_text(img, &[])
}

/// PNG file bytes of an RGB image with `tEXt` chunks of `(keyword, text)`, which image viewers
/// and `PIL.Image.open(path).text` show (keywords of 1–79 Latin-1 characters, Latin-1 text).
/// Compressed as `image` compresses by default, so without text the bytes are the same.
pub fn encode_png_with_text(img: &RgbImage, text: &[(&str, &str)]) -> Result<Vec<u8>, ImageIoError> {
    check(img)?;
    let failed = |e: png::EncodingError| ImageIoError::PngText(e.to_string());
    let mut out = Vec::new();
    let mut encoder = png::Encoder::new(&mut out, img.width, img.height);
    encoder.set_color(png::ColorType::Rgb);
    encoder.set_depth(png::BitDepth::Eight);
    encoder.set_compression(png::Compression::Fast);
    encoder.set_filter(png::Filter::Adaptive);
    for (keyword, value) in text {
        encoder.add_text_chunk(keyword.to_string(), value.to_string()).map_err(failed)?;
    }
    let mut writer = encoder.write_header().map_err(failed)?;
    writer.write_image_data(&img.data).map_err(failed)?;
    writer.finish().map_err(failed)?;
    Ok(out)
}

/// Decodes PNG bytes to RGB (grey is expanded, alpha dropped); `name` is used in errors.
pub fn decode_png(bytes: &[u8], name: &str) -> Result<RgbImage, ImageIoError> {
    let img = image::load_from_memory_with_format(bytes, image::ImageFormat::Png)
        .map_err(|source| ImageIoError::Png { context: name.to_string(), source })?
        .into_rgb8();
    let (width, height) = img.dimensions();
    Ok(RgbImage { width, height, data: img.into_raw() })
}

/// Decodes PNG bytes to RGBA8 (what textures need); `name` is used in errors.
pub fn decode_png_rgba(bytes: &[u8], name: &str) -> Result<(u32, u32, Vec<u8>), ImageIoError> {
    let img = image::load_from_memory_with_format(bytes, image::ImageFormat::Png)
        .map_err(|source| ImageIoError::Png { context: name.to_string(), source })?
        .into_rgba8();
    let (w, h) = img.dimensions();
    Ok((w, h, img.into_raw()))
}

/// Writes a PNG file.
pub fn save_png(img: &RgbImage, path: impl AsRef<Path>) -> Result<(), ImageIoError> {
    save_png_with_text(img, path, &[])
}

/// Writes a PNG file with `tEXt` chunks ([`encode_png_with_text`]).
pub fn save_png_with_text(img: &RgbImage, path: impl AsRef<Path>, text: &[(&str, &str)]) -> Result<(), ImageIoError> {
    let path = path.as_ref();
    let bytes = encode_png_with_text(img, text)?;
    std::fs::write(path, bytes).map_err(|source| ImageIoError::Io { path: path.display().to_string(), source })
}

/// Reads a PNG file as RGB.
pub fn load_png(path: impl AsRef<Path>) -> Result<RgbImage, ImageIoError> {
    let path = path.as_ref();
    let bytes = std::fs::read(path).map_err(|source| ImageIoError::Io { path: path.display().to_string(), source })?;
    decode_png(&bytes, &path.display().to_string())
}

/// `left` and `right` next to each other, top-aligned, with `gap` black columns between them;
/// the shorter one is padded with black below.
pub fn side_by_side(left: &RgbImage, right: &RgbImage, gap: u32) -> RgbImage {
    let width = left.width + gap + right.width;
    let height = left.height.max(right.height);
    let mut out = RgbImage::new(width, height);
    for (img, x0) in [(left, 0), (right, left.width + gap)] {
        let row = img.width as usize * 3;
        for y in 0..img.height as usize {
            let Some(src) = img.data.get(y * row..(y + 1) * row) else { break };
            let start = (y * width as usize + x0 as usize) * 3;
            out.data[start..start + row].copy_from_slice(src);
        }
    }
    out
}

/// Writes an animated, looping GIF one frame at a time (each frame gets its own 256-colour
/// palette). Output bytes depend only on the frames.
pub struct GifWriter<W: Write> {
    encoder: gif::Encoder<W>,
    width: u32,
    height: u32,
    /// Frame duration in hundredths of a second.
    delay: u16,
}

impl<W: Write> GifWriter<W> {
    /// Starts a `width × height` GIF playing at `fps` frames per second (GIF timing has
    /// 1/100 s resolution).
    pub fn new(writer: W, width: u32, height: u32, fps: f32) -> Result<GifWriter<W>, ImageIoError> {
        let (Ok(w), Ok(h)) = (u16::try_from(width), u16::try_from(height)) else {
            return Err(ImageIoError::Size(format!("GIF size {width}×{height} exceeds 65535")));
        };
        if !(fps > 0.0 && fps.is_finite()) {
            return Err(ImageIoError::Size(format!("GIF frame rate {fps} must be positive")));
        }
        let mut encoder = gif::Encoder::new(writer, w, h, &[])?;
        encoder.set_repeat(gif::Repeat::Infinite)?;
        let delay = (100.0 / fps).round().clamp(1.0, u16::MAX as f32) as u16;
        Ok(GifWriter { encoder, width, height, delay })
    }

    /// Writes a comment into the file (GIF's comment extension, which `exiftool` and
    /// `PIL.Image.open(path).info["comment"]` show), e.g. the look that drew the frames.
    pub fn comment(&mut self, text: &str) -> Result<(), ImageIoError> {
        self.encoder.write_raw_extension(gif::AnyExtension(0xFE), &[text.as_bytes()])?;
        Ok(())
    }

    /// Appends a frame of the writer's size.
    pub fn add_frame(&mut self, img: &RgbImage) -> Result<(), ImageIoError> {
        check(img)?;
        if (img.width, img.height) != (self.width, self.height) {
            return Err(ImageIoError::Size(format!(
                "GIF frame is {}×{} but the animation is {}×{}",
                img.width, img.height, self.width, self.height
            )));
        }
        let mut frame = gif::Frame::from_rgb_speed(self.width as u16, self.height as u16, &img.data, 10);
        frame.delay = self.delay;
        self.encoder.write_frame(&frame)?;
        Ok(())
    }

    /// Finishes the file and returns the writer.
    pub fn finish(self) -> Result<W, ImageIoError> {
        Ok(self.encoder.into_inner()?)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn gradient(w: u32, h: u32) -> RgbImage {
        let mut img = RgbImage::new(w, h);
        for y in 0..h {
            for x in 0..w {
                img.set_pixel(x, y, [(x * 7) as u8, (y * 5) as u8, ((x + y) * 3) as u8]);
            }
        }
        img
    }

    #[test]
    fn png_round_trip_is_lossless() {
        let img = gradient(33, 17);
        let bytes = encode_png(&img).unwrap();
        assert_eq!(&bytes[1..4], b"PNG");
        assert_eq!(decode_png(&bytes, "mem").unwrap(), img);
    }

    #[test]
    fn png_text_chunks_are_read_back_beside_the_same_pixels() {
        let img = gradient(20, 9);
        let bytes = encode_png_with_text(&img, &[("look", "libero-assets:5ffbda9a79ff3d71"), ("task", "libero_spatial/0")]).unwrap();
        assert_eq!(decode_png(&bytes, "mem").unwrap(), img);
        let reader = png::Decoder::new(std::io::Cursor::new(&bytes)).read_info().unwrap();
        let text: Vec<(&str, &str)> = reader.info().uncompressed_latin1_text.iter().map(|t| (t.keyword.as_str(), t.text.as_str())).collect();
        assert_eq!(text, [("look", "libero-assets:5ffbda9a79ff3d71"), ("task", "libero_spatial/0")]);
        // PNG keywords are 1-79 characters: an empty one is an error, not a panic or a bad file.
        assert!(matches!(encode_png_with_text(&img, &[("", "x")]), Err(ImageIoError::PngText(_))));
    }

    #[test]
    fn corrupt_png_is_an_error_naming_the_source() {
        let err = decode_png(b"\x89PNG\r\n\x1a\nnot really", "cue.png").unwrap_err();
        assert!(err.to_string().starts_with("cue.png"), "{err}");
        let bad = RgbImage { width: 4, height: 4, data: vec![0; 5] };
        assert!(matches!(encode_png(&bad), Err(ImageIoError::Size(_))));
    }

    #[test]
    fn side_by_side_places_and_pads() {
        let a = RgbImage::filled(2, 3, [10, 10, 10]);
        let b = RgbImage::filled(3, 1, [200, 0, 0]);
        let s = side_by_side(&a, &b, 1);
        assert_eq!((s.width, s.height), (6, 3));
        assert_eq!(s.pixel(1, 2), [10, 10, 10]);
        assert_eq!(s.pixel(2, 0), [0, 0, 0]);
        assert_eq!(s.pixel(3, 0), [200, 0, 0]);
        assert_eq!(s.pixel(3, 1), [0, 0, 0]);
    }

    #[test]
    fn gif_has_all_frames_and_is_deterministic() {
        let make = || {
            let mut g = GifWriter::new(Vec::new(), 16, 8, 20.0).unwrap();
            for k in 0..3 {
                let mut img = gradient(16, 8);
                img.set_pixel(k, 0, [255, 255, 255]);
                g.add_frame(&img).unwrap();
            }
            assert!(g.add_frame(&gradient(8, 8)).is_err());
            g.finish().unwrap()
        };
        let a = make();
        assert_eq!(&a[..6], b"GIF89a");
        let mut commented = GifWriter::new(Vec::new(), 16, 8, 20.0).unwrap();
        commented.comment("look: built-in").unwrap();
        commented.add_frame(&gradient(16, 8)).unwrap();
        let c = commented.finish().unwrap();
        assert!(c.windows(17).any(|w| w == b"\x21\xFE\x0Elook: built-in"), "comment extension block");
        // Three image descriptors (0x2C) after graphic control extensions with 5 cs delay.
        let delays = a.windows(4).filter(|w| w[0] == 0x21 && w[1] == 0xF9 && w[2] == 4).count();
        assert_eq!(delays, 3);
        assert_eq!(a, make());
    }
}

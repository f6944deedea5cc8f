//! Render outputs and the image-orientation helpers VLA pipelines need.
//!
//! Frames come out upright: row 0 is the top of the image, as [`crate::Camera`] defines pixels.
//! robosuite returns images bottom-up (OpenGL order): [`Frame::flip_vertical`] gives that.
//! LIBERO/OpenVLA pipelines feed the policy the image rotated by 180° (`img[::-1, ::-1]` of the
//! robosuite array, which equals rotating the upright image): [`Frame::rotate_180`].

/// An 8-bit RGB image, rows top to bottom, tightly packed.
#[derive(Clone, Debug, PartialEq, Eq, Default)]
pub struct RgbImage {
    pub width: u32,
    pub height: u32,
    /// `width × height × 3` bytes.
    pub data: Vec<u8>,
}

impl RgbImage {
    /// A black image.
    pub fn new(width: u32, height: u32) -> RgbImage {
        RgbImage::filled(width, height, [0, 0, 0])
    }

    /// An image of one colour.
    pub fn filled(width: u32, height: u32, rgb: [u8; 3]) -> RgbImage {
        let n = width as usize * height as usize;
        let mut data = Vec::with_capacity(n * 3);
        for _ in 0..n {
            data.extend_from_slice(&rgb);
        }
        RgbImage { width, height, data }
    }

    /// Wraps packed RGB bytes; `None` if the length does not match the size.
    pub fn from_raw(width: u32, height: u32, data: Vec<u8>) -> Option<RgbImage> {
        (data.len() == width as usize * height as usize * 3).then_some(RgbImage { width, height, data })
    }

    /// The pixel at column `x`, row `y`.
    pub fn pixel(&self, x: u32, y: u32) -> [u8; 3] {
        let i = (y as usize * self.width as usize + x as usize) * 3;
        [self.data[i], self.data[i + 1], self.data[i + 2]]
    }

    /// Sets the pixel at column `x`, row `y`.
    pub fn set_pixel(&mut self, x: u32, y: u32, rgb: [u8; 3]) {
        let i = (y as usize * self.width as usize + x as usize) * 3;
        self.data[i..i + 3].copy_from_slice(&rgb);
    }

    /// Reverses the row order in place (upright ↔ OpenGL bottom-up).
    pub fn flip_vertical(&mut self) {
        flip_rows(&mut self.data, self.width as usize * 3, self.height as usize);
    }

    /// Rotates by 180° in place.
    pub fn rotate_180(&mut self) {
        reverse_pixels(&mut self.data, 3);
    }
}

/// One rendered view: colour, depth and segmentation, all upright (row 0 at the top).
#[derive(Clone, Debug, PartialEq, Default)]
pub struct Frame {
    pub color: RgbImage,
    /// Distance along the view axis in metres, row-major; `f32::INFINITY` where nothing was drawn.
    pub depth: Vec<f32>,
    /// [`crate::Instance::segment`] of the visible surface, row-major; 0 where nothing was drawn.
    pub segmentation: Vec<u32>,
}

impl Frame {
    /// A frame of the given size, black with empty depth and segmentation.
    pub fn new(width: u32, height: u32) -> Frame {
        let n = width as usize * height as usize;
        Frame { color: RgbImage::new(width, height), depth: vec![f32::INFINITY; n], segmentation: vec![0; n] }
    }

    pub fn width(&self) -> u32 {
        self.color.width
    }

    pub fn height(&self) -> u32 {
        self.color.height
    }

    /// Depth at column `x`, row `y`.
    pub fn depth_at(&self, x: u32, y: u32) -> f32 {
        self.depth[y as usize * self.width() as usize + x as usize]
    }

    /// Segment id at column `x`, row `y`.
    pub fn segment_at(&self, x: u32, y: u32) -> u32 {
        self.segmentation[y as usize * self.width() as usize + x as usize]
    }

    /// Reverses the row order of all three layers (upright ↔ robosuite's OpenGL order).
    pub fn flip_vertical(&mut self) {
        self.color.flip_vertical();
        let (w, h) = (self.width() as usize, self.height() as usize);
        flip_rows(&mut self.depth, w, h);
        flip_rows(&mut self.segmentation, w, h);
    }

    /// Rotates all three layers by 180° (what LIBERO VLA pipelines feed the policy).
    pub fn rotate_180(&mut self) {
        self.color.rotate_180();
        self.depth.reverse();
        self.segmentation.reverse();
    }

    /// Resizes the layers for a new image size (contents unspecified until the next render).
    pub(crate) fn resize(&mut self, width: u32, height: u32) {
        let n = width as usize * height as usize;
        self.color.width = width;
        self.color.height = height;
        self.color.data.resize(n * 3, 0);
        self.depth.resize(n, f32::INFINITY);
        self.segmentation.resize(n, 0);
    }
}

/// Reverses the order of the `rows` rows of `row_len` items (only whole rows present in
/// `data` take part, so inconsistent sizes cannot make it panic).
fn flip_rows<T>(data: &mut [T], row_len: usize, rows: usize) {
    if row_len == 0 {
        return;
    }
    let rows = rows.min(data.len() / row_len);
    for y in 0..rows / 2 {
        let (top, bottom) = data.split_at_mut((rows - 1 - y) * row_len);
        top[y * row_len..(y + 1) * row_len].swap_with_slice(&mut bottom[..row_len]);
    }
}

/// Reverses the order of `channels`-byte pixels.
fn reverse_pixels(data: &mut [u8], channels: usize) {
    let n = data.len() / channels;
    for i in 0..n / 2 {
        let j = n - 1 - i;
        for c in 0..channels {
            data.swap(i * channels + c, j * channels + c);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn numbered() -> Frame {
        let mut f = Frame::new(3, 2);
        for y in 0..2 {
            for x in 0..3 {
                let k = (y * 3 + x) as u8;
                f.color.set_pixel(x, y, [k, k + 10, k + 20]);
                f.segmentation[(y * 3 + x) as usize] = k as u32;
                f.depth[(y * 3 + x) as usize] = k as f32;
            }
        }
        f
    }

    #[test]
    fn flip_vertical_swaps_rows() {
        let mut f = numbered();
        f.flip_vertical();
        assert_eq!(f.color.pixel(0, 0), [3, 13, 23]);
        assert_eq!(f.segment_at(2, 1), 2);
        assert_eq!(f.depth_at(1, 0), 4.0);
        f.flip_vertical();
        assert_eq!(f, numbered());
    }

    #[test]
    fn inconsistent_sizes_do_not_panic() {
        let mut img = RgbImage { width: 4, height: 4, data: vec![1; 10] };
        img.flip_vertical();
        img.rotate_180();
        assert_eq!(img.data.len(), 10);
    }

    #[test]
    fn rotate_180_equals_both_flips() {
        let mut f = numbered();
        f.rotate_180();
        assert_eq!(f.color.pixel(0, 0), [5, 15, 25]);
        assert_eq!(f.color.pixel(2, 1), [0, 10, 20]);
        assert_eq!(f.segment_at(1, 0), 4);
        assert_eq!(f.depth_at(0, 1), 2.0);
    }
}

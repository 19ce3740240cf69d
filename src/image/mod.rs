//! Images: the [`Image`] type every render ends in, EXR and PNG files, error metrics.
//!
//! - [`exr`]: read (RGB or RGBA, half or float, as Mitsuba and others write them) and
//!   write (RGB float32, or any channels in half or float) OpenEXR files.
//! - [`png`]: 8-bit sRGB PNG output for looking at a render: exposure, clamp, sRGB OETF.
//! - [`pfm`], [`rgbe`]: portable float maps and Radiance RGBE files (Mitsuba's other
//!   film file formats).
//! - [`tev`]: streaming an image in progress to the tev viewer over TCP.
//! - [`metrics`]: MSE, RMSE, relative MSE, per-channel means, and the blockwise
//!   t-test that image tests use to compare a noisy render with a reference.

pub mod error;
pub mod exr;
pub mod metrics;
pub mod pfm;
pub mod png;
pub mod rgbe;
pub mod tev;

pub use error::Error;

/// The most texels (width x height) an image file may have: 2^27, a 16384 x 8192
/// environment map, 1.5 GiB as float RGB. Readers check a file's header against it
/// before they allocate anything, so a header claiming 10^9 x 10^9 pixels in a few
/// bytes is an error, not an allocation. Fuzz builds (`tools/fuzz.sh`) lower it to
/// 2^20, so that the fuzzer explores files instead of decoding a large image from
/// each small one that claims it.
pub const MAX_TEXELS: u64 = if cfg!(fuzzing) { 1 << 20 } else { 1 << 27 };

/// An error unless a `width` x `height` image is within [`MAX_TEXELS`].
pub fn check_texels(width: u64, height: u64) -> Result<(), String> {
    match width.checked_mul(height) {
        Some(n) if n <= MAX_TEXELS => Ok(()),
        _ => Err(format!(
            "{width} x {height} pixels is more than wavetrace reads (2^{} texels)",
            MAX_TEXELS.ilog2()
        )),
    }
}

/// A linear RGB image: 3 floats per pixel, row-major, top row first.
///
/// Values are scene-referred radiance (or AO, or whatever the integrator measures),
/// not display values: nothing is clamped or gamma-encoded until [`png`] writes it.
#[derive(Debug, Clone, PartialEq)]
pub struct Image {
    pub width: u32,
    pub height: u32,
    /// `rgb[3 * (y * width + x) + c]` is channel `c` of pixel `(x, y)`.
    pub rgb: Vec<f32>,
}

impl Image {
    /// A black image.
    pub fn new(width: u32, height: u32) -> Self {
        Self {
            width,
            height,
            rgb: vec![0.0; 3 * width as usize * height as usize],
        }
    }

    /// An image over existing pixel data; `None` unless `rgb.len() == 3 * width * height`.
    pub fn from_rgb(width: u32, height: u32, rgb: Vec<f32>) -> Option<Self> {
        (rgb.len() == 3 * width as usize * height as usize).then_some(Self { width, height, rgb })
    }

    /// Number of pixels.
    pub fn pixel_count(&self) -> usize {
        self.width as usize * self.height as usize
    }

    /// The pixel at column `x`, row `y` (row 0 at the top). Panics outside the image.
    pub fn pixel(&self, x: u32, y: u32) -> [f32; 3] {
        let i = self.index(x, y);
        [self.rgb[i], self.rgb[i + 1], self.rgb[i + 2]]
    }

    /// Sets the pixel at column `x`, row `y`. Panics outside the image.
    pub fn set_pixel(&mut self, x: u32, y: u32, value: [f32; 3]) {
        let i = self.index(x, y);
        self.rgb[i..i + 3].copy_from_slice(&value);
    }

    /// How many channel values are NaN or infinite (a correct render has none).
    pub fn non_finite_count(&self) -> usize {
        self.rgb.iter().filter(|v| !v.is_finite()).count()
    }

    /// Reads an EXR file; see [`exr::read`].
    pub fn read_exr(path: impl AsRef<std::path::Path>) -> Result<Self, Error> {
        exr::read(path)
    }

    /// Writes an RGB float32 EXR file; see [`exr::write`].
    pub fn write_exr(&self, path: impl AsRef<std::path::Path>) -> Result<(), Error> {
        exr::write(self, path)
    }

    /// Writes an 8-bit sRGB PNG, `exposure` in stops (0 leaves values as they are);
    /// see [`png::write`].
    pub fn write_png(&self, path: impl AsRef<std::path::Path>, exposure: f32) -> Result<(), Error> {
        png::write(self, path, exposure)
    }

    fn index(&self, x: u32, y: u32) -> usize {
        assert!(
            x < self.width && y < self.height,
            "pixel ({x}, {y}) outside a {}x{} image",
            self.width,
            self.height
        );
        3 * (y as usize * self.width as usize + x as usize)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pixels_are_row_major_top_first() {
        let mut image = Image::new(3, 2);
        image.set_pixel(2, 1, [1.0, 2.0, 3.0]);
        assert_eq!(&image.rgb[15..18], &[1.0, 2.0, 3.0]);
        assert_eq!(image.pixel(2, 1), [1.0, 2.0, 3.0]);
        assert_eq!(image.pixel(0, 0), [0.0; 3]);
    }

    #[test]
    fn from_rgb_checks_length() {
        assert!(Image::from_rgb(2, 2, vec![0.0; 12]).is_some());
        assert!(Image::from_rgb(2, 2, vec![0.0; 11]).is_none());
    }

    #[test]
    fn counts_non_finite_values() {
        let image = Image::from_rgb(1, 2, vec![0.0, f32::NAN, 1.0, f32::INFINITY, 2.0, 3.0]);
        assert_eq!(image.map(|i| i.non_finite_count()), Some(2));
    }
}

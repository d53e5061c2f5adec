//! Image metrics against a reference: root-mean-square error and PSNR over linear RGB.

use super::Film;

/// Root-mean-square error over all channels of two films of the same size (`None` if the
/// sizes differ).
pub fn rmse(image: &Film, reference: &Film) -> Option<f64> {
    if (image.width, image.height) != (reference.width, reference.height) {
        return None;
    }
    let n = image.pixels.len() * 3;
    if n == 0 {
        return Some(0.0);
    }
    let sum: f64 = image
        .pixels
        .iter()
        .zip(&reference.pixels)
        .map(|(a, b)| (*a - *b).to_array().iter().map(|d| f64::from(*d).powi(2)).sum::<f64>())
        .sum();
    Some((sum / n as f64).sqrt())
}

/// Peak signal-to-noise ratio in dB for a peak value of 1 (∞ for identical films).
pub fn psnr(image: &Film, reference: &Film) -> Option<f64> {
    rmse(image, reference).map(|e| -20.0 * e.log10())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Vec3;

    #[test]
    fn rmse_of_a_uniform_offset_is_the_offset() {
        let a = Film::new(4, 3);
        let mut b = Film::new(4, 3);
        b.pixels.iter_mut().for_each(|p| *p = Vec3::splat(0.25));
        assert!((rmse(&a, &b).unwrap() - 0.25).abs() < 1e-12);
        assert!((psnr(&a, &b).unwrap() - 12.0412).abs() < 1e-3);
        assert_eq!(rmse(&a, &a), Some(0.0));
        assert_eq!(psnr(&a, &a), Some(f64::INFINITY));
        assert_eq!(rmse(&a, &Film::new(3, 4)), None);
    }

    #[test]
    fn rmse_weights_every_channel_equally() {
        let a = Film::new(1, 1);
        let mut b = Film::new(1, 1);
        b.pixels[0] = Vec3::new(0.3, 0.0, 0.0);
        assert!((rmse(&a, &b).unwrap() - 0.3 / 3f64.sqrt()).abs() < 1e-7);
    }
}

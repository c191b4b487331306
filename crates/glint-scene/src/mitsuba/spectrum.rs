//! Sampled spectra (`<spectrum value="400:0.1, 500:0.4, …"/>`) turned into linear sRGB the way
//! Mitsuba 3's RGB variants turn them, so that a spectral scene renders the colours Mitsuba's
//! references show:
//!
//! * the values are interpolated linearly between the given wavelengths and are zero outside
//!   them;
//! * the curve is integrated against the CIE 1931 colour-matching functions (tabulated every
//!   5 nm, interpolated linearly) over 360–830 nm by Mitsuba's quadrature, 1000 points with
//!   weight 470/1000 nm, and divided by the same quadrature of ȳ (so a constant 1 has Y = 1);
//! * a reflectance is seen under D65 (its curve multiplied by D65 / 98.997…, which makes a
//!   white reflector white); an emitter's radiance is taken as it is;
//! * XYZ goes to linear sRGB by the sRGB (D65) matrix; a reflectance is clamped to [0, 1],
//!   anything else (radiance, η, k) only to ≥ 0.

use super::cie_tables::{D65, FIRST_NM, LAST_NM, SAMPLES, X_BAR, Y_BAR, Z_BAR};

/// What a spectrum stands for, which decides its illuminant and its clamping.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SpectrumRole {
    /// A reflectance or transmittance: under D65, clamped to [0, 1].
    Reflectance,
    /// An emitter's radiance, intensity or irradiance.
    Emission,
    /// An index of refraction or extinction coefficient (`eta`, `k`, `int_ior`, `ext_ior`).
    Unbounded,
}

impl SpectrumRole {
    /// The role Mitsuba gives a property `name` read inside an `<emitter>` or not.
    pub fn of(name: &str, within_emitter: bool) -> Self {
        if within_emitter {
            Self::Emission
        } else if matches!(name, "eta" | "k" | "int_ior" | "ext_ior") {
            Self::Unbounded
        } else {
            Self::Reflectance
        }
    }
}

/// Mitsuba's constants: 1 / (its quadrature of ȳ) and 1 / (its normalisation of D65).
const Y_NORMALIZATION: f64 = 1.0 / 106.750_259_399_414_06;
const D65_NORMALIZATION: f64 = 1.0 / 98.997_417_518_762_55;
const QUADRATURE_POINTS: usize = 1000;

/// `(wavelength in nm, value)` pairs in increasing wavelength, as linear sRGB, and whether
/// the result had to be clamped.
pub fn sampled_to_rgb(samples: &[(f64, f64)], role: SpectrumRole) -> ([f32; 3], bool) {
    let mut xyz = [0.0f64; 3];
    for i in 0..QUADRATURE_POINTS {
        let lambda = FIRST_NM + i as f64 / (QUADRATURE_POINTS - 1) as f64 * (LAST_NM - FIRST_NM);
        let Some(mut value) = interpolate(samples, lambda) else { continue };
        value *= Y_NORMALIZATION;
        if role == SpectrumRole::Reflectance {
            value *= tabulated(&D65, lambda) * D65_NORMALIZATION;
        }
        for (sum, table) in xyz.iter_mut().zip([&X_BAR, &Y_BAR, &Z_BAR]) {
            *sum += tabulated(table, lambda) * value;
        }
    }
    let weight = (LAST_NM - FIRST_NM) / QUADRATURE_POINTS as f64;
    let [x, y, z] = xyz.map(|c| c * weight);
    let rgb = [
        3.240479 * x - 1.537150 * y - 0.498535 * z,
        -0.969256 * x + 1.875991 * y + 0.041556 * z,
        0.055648 * x - 0.204043 * y + 1.057311 * z,
    ];
    let upper = if role == SpectrumRole::Reflectance { 1.0 } else { f64::INFINITY };
    let clamped = rgb.iter().any(|&c| !(0.0..=upper).contains(&c));
    (rgb.map(|c| c.clamp(0.0, upper) as f32), clamped)
}

/// The spectrum at `lambda`: linear between samples, `None` outside them.
fn interpolate(samples: &[(f64, f64)], lambda: f64) -> Option<f64> {
    let (first, last) = (samples.first()?, samples.last()?);
    if lambda < first.0 || lambda > last.0 {
        return None;
    }
    let upper = samples.partition_point(|&(w, _)| w < lambda).clamp(1, samples.len() - 1);
    let ((w0, v0), (w1, v1)) = (samples[upper - 1], samples[upper]);
    if samples.len() == 1 || w1 <= w0 {
        return Some(v1);
    }
    let t = (lambda - w0) / (w1 - w0);
    Some(v0 + t * (v1 - v0))
}

/// A 5 nm table at `lambda` (linear between entries, zero outside 360–830 nm).
pub(crate) fn tabulated(table: &[f64; SAMPLES], lambda: f64) -> f64 {
    if !(FIRST_NM..=LAST_NM).contains(&lambda) {
        return 0.0;
    }
    let position = (lambda - FIRST_NM) / 5.0;
    let i = (position as usize).min(SAMPLES - 2);
    let t = position - i as f64;
    table[i] * (1.0 - t) + table[i + 1] * t
}

/// Parses `400:0.1, 500:0.4 …` (commas or spaces between pairs) into increasing pairs.
pub fn parse_sampled(text: &str) -> Result<Vec<(f64, f64)>, String> {
    let mut samples: Vec<(f64, f64)> = Vec::new();
    for token in text.split(|c: char| c == ',' || c.is_whitespace()).filter(|t| !t.is_empty()) {
        let (w, v) = token.split_once(':').ok_or_else(|| format!("expected wavelength:value pairs, got `{token}`"))?;
        let parse = |s: &str| s.trim().parse::<f64>().ok().filter(|x| x.is_finite());
        let (Some(w), Some(v)) = (parse(w), parse(v)) else {
            return Err(format!("cannot read the wavelength:value pair `{token}`"));
        };
        if samples.last().is_some_and(|&(previous, _)| w <= previous) {
            return Err(format!("wavelengths must increase, and {w} follows {}", samples.last().unwrap().0));
        }
        samples.push((w, v));
    }
    if samples.is_empty() {
        return Err("an empty spectrum".into());
    }
    Ok(samples)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn constant(value: f64) -> Vec<(f64, f64)> {
        vec![(FIRST_NM, value), (LAST_NM, value)]
    }

    #[test]
    fn a_constant_emission_has_unit_luminance_and_the_colour_of_equal_energy() {
        let (rgb, clamped) = sampled_to_rgb(&constant(1.0), SpectrumRole::Emission);
        assert!(!clamped);
        let luminance = 0.212671 * rgb[0] + 0.715160 * rgb[1] + 0.072169 * rgb[2];
        assert!((luminance - 1.0).abs() < 1e-4, "{rgb:?}");
        // Illuminant E in sRGB: reddish and short of blue (x = y = 1/3 against D65's white).
        assert!(rgb[0] > 1.15 && rgb[2] < 0.95, "{rgb:?}");
    }

    #[test]
    fn a_white_reflectance_is_white_under_d65_and_a_grey_one_grey() {
        for value in [1.0, 0.5, 0.25] {
            let (rgb, _) = sampled_to_rgb(&constant(value), SpectrumRole::Reflectance);
            for c in rgb {
                assert!((c as f64 - value).abs() < 0.01 * value, "{value}: {rgb:?}");
            }
        }
    }

    #[test]
    fn a_spectrum_is_zero_outside_its_wavelengths() {
        // Only 700–830 nm: deep red, and far dimmer than the same value everywhere.
        let (rgb, _) = sampled_to_rgb(&[(700.0, 1.0), (830.0, 1.0)], SpectrumRole::Emission);
        assert!(rgb[0] > 0.0 && rgb[0] < 0.05 && rgb[1] == 0.0, "{rgb:?}");
        assert_eq!(interpolate(&[(400.0, 2.0), (500.0, 4.0)], 450.0), Some(3.0));
        assert_eq!(interpolate(&[(400.0, 2.0), (500.0, 4.0)], 399.0), None);
        assert_eq!(interpolate(&[(400.0, 2.0), (500.0, 4.0)], 500.0), Some(4.0));
    }

    #[test]
    fn reflectances_clamp_and_radiance_does_not() {
        let (rgb, clamped) = sampled_to_rgb(&constant(3.0), SpectrumRole::Reflectance);
        assert!(clamped && rgb == [1.0; 3], "{rgb:?}");
        let (rgb, clamped) = sampled_to_rgb(&constant(3.0), SpectrumRole::Emission);
        assert!(!clamped && rgb[0] > 3.0, "{rgb:?}");
    }

    #[test]
    fn parsing() {
        assert_eq!(parse_sampled("400:0, 500:8,600:15.6 700:18.4").unwrap().len(), 4);
        assert!(parse_sampled("400:1, 300:2").unwrap_err().contains("increase"));
        assert!(parse_sampled("400").unwrap_err().contains("pairs"));
        assert!(parse_sampled("400:x").is_err());
    }

    #[test]
    fn roles() {
        assert_eq!(SpectrumRole::of("radiance", true), SpectrumRole::Emission);
        assert_eq!(SpectrumRole::of("eta", false), SpectrumRole::Unbounded);
        assert_eq!(SpectrumRole::of("reflectance", false), SpectrumRole::Reflectance);
    }
}

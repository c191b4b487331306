//! pbrt-v4's spectra as the RGB its `rgb` film records with the default (`cie1931`) sensor:
//!
//! * a light's spectrum is scaled to luminance 1 (`scale /= SpectrumToPhotometric(L)`), except
//!   an `rgb` value, which keeps its own magnitude: `"rgb L" [a b c]` is recorded as (a, b, c);
//!   so a blackbody or a named illuminant is its colour at Y = 1;
//! * a reflectance given as samples is seen under D65 (the sRGB white), as glint's Mitsuba
//!   reader sees it;
//! * indices of refraction given by name (pbrt's glasses) are the glass's index at the
//!   helium d line (587.6 nm), where an RGB renderer cannot split wavelengths; metals given by
//!   name are glint's measured RGB η and k of the same metal.

use crate::mitsuba::cie_tables::{X_BAR, Y_BAR, Z_BAR};
use crate::mitsuba::spectrum::{sampled_to_rgb, tabulated, SpectrumRole};

#[derive(Clone, Debug, PartialEq)]
pub enum Spectrum {
    Rgb([f32; 3]),
    /// A temperature in kelvin.
    Blackbody(f64),
    Named(String),
    /// Wavelength (nm)–value pairs, wavelengths increasing.
    Sampled(Vec<(f64, f64)>),
}

/// pbrt's glasses: (name, Schott's n_d; pbrt's F5, F10 and F11 tables are the dense flints
/// SF5, SF10 and SF11).
const GLASSES: [(&str, f32); 7] = [
    ("glass-BK7", 1.5168),
    ("glass-BAF10", 1.6700),
    ("glass-FK51A", 1.4866),
    ("glass-LASF9", 1.8503),
    ("glass-F5", 1.6727),
    ("glass-F10", 1.7283),
    ("glass-F11", 1.7847),
];

/// pbrt's metals glint knows, by pbrt's name (`metal-Cu-eta` → `Cu`).
const METALS: [&str; 4] = ["Ag", "Al", "Au", "Cu"];

/// A light's colour.
pub fn emission(s: &Spectrum) -> Result<[f32; 3], String> {
    match s {
        Spectrum::Rgb(rgb) => non_negative(*rgb),
        Spectrum::Blackbody(t) => {
            if !(t.is_finite() && *t > 0.0) {
                return Err(format!("a blackbody's temperature must be > 0 K, got {t}"));
            }
            Ok(unit_luminance(|lambda| planck(lambda, *t)))
        }
        Spectrum::Named(name) => match name.as_str() {
            // Both normalised to luminance 1: D65 is the sRGB white.
            "stdillum-D65" => Ok([1.0; 3]),
            // CIE illuminant A is, by definition, a blackbody at 2856 K.
            "stdillum-A" => Ok(unit_luminance(|lambda| planck(lambda, 2856.0))),
            _ => Err(format!(
                "the spectrum `{name}` is not available for a light; glint knows stdillum-D65 and stdillum-A (give an rgb or a blackbody)"
            )),
        },
        Spectrum::Sampled(samples) => Ok(unit_luminance(|lambda| interpolate(samples, lambda))),
    }
}

/// A reflectance or transmittance in [0, 1].
pub fn albedo(s: &Spectrum) -> Result<[f32; 3], String> {
    match s {
        Spectrum::Rgb(rgb) => {
            if rgb.iter().any(|c| !(0.0..=1.0).contains(c)) {
                return Err(format!("a reflectance's rgb must lie in [0, 1] (as pbrt requires), got {rgb:?}"));
            }
            Ok(*rgb)
        }
        Spectrum::Sampled(samples) => Ok(sampled_to_rgb(samples, SpectrumRole::Reflectance).0),
        Spectrum::Blackbody(_) => Err("a blackbody is a light's spectrum, not a reflectance".into()),
        Spectrum::Named(name) => Err(format!("the named spectrum `{name}` is not a reflectance")),
    }
}

/// An index of refraction.
pub fn index(s: &Spectrum) -> Result<f32, String> {
    match s {
        Spectrum::Named(name) => GLASSES.iter().find(|(n, _)| n == name).map(|&(_, eta)| eta).ok_or_else(|| {
            format!(
                "unknown glass `{name}`; pbrt's are {}",
                GLASSES.iter().map(|(n, _)| *n).collect::<Vec<_>>().join(", ")
            )
        }),
        Spectrum::Rgb(rgb) => Ok((rgb[0] + rgb[1] + rgb[2]) / 3.0),
        Spectrum::Sampled(samples) => Ok(interpolate(samples, 587.6) as f32),
        Spectrum::Blackbody(_) => Err("a blackbody is not an index of refraction".into()),
    }
}

/// A metal named by both its η and k spectra (`metal-Au-eta`, `metal-Au-k`): glint's name.
pub fn metal(eta: &str, k: &str) -> Result<&'static str, String> {
    let metal_of =
        |name: &str, suffix: &str| name.strip_prefix("metal-").and_then(|n| n.strip_suffix(suffix)).map(str::to_string);
    match (metal_of(eta, "-eta"), metal_of(k, "-k")) {
        (Some(a), Some(b)) if a == b => METALS.iter().find(|m| **m == a).copied().ok_or_else(|| {
            format!(
                "glint has no measured data for the metal `{a}`; it knows {} (or give rgb eta and k)",
                METALS.join(", ")
            )
        }),
        (Some(a), Some(b)) => Err(format!("η of `{a}` with k of `{b}`: give both of one metal")),
        _ => Err(format!("`{eta}`/`{k}` are not pbrt's metal spectra (metal-Cu-eta, metal-Cu-k, …)")),
    }
}

/// A `.spd` file's wavelength (nm)–value pairs, as pbrt reads them: numbers separated by
/// white space, `#` to the end of a line a comment, wavelengths increasing.
pub fn read_spd(text: &str) -> Result<Vec<(f64, f64)>, String> {
    let mut numbers = Vec::new();
    for line in text.lines() {
        let line = line.split('#').next().unwrap_or("");
        for word in line.split_whitespace() {
            let x: f64 = word.parse().map_err(|_| format!("`{word}` is not a number"))?;
            if !x.is_finite() {
                return Err(format!("`{word}` is not a finite number"));
            }
            numbers.push(x);
        }
    }
    if numbers.len() < 2 || numbers.len() % 2 != 0 {
        return Err(format!("expected wavelength–value pairs, got {} numbers", numbers.len()));
    }
    let pairs: Vec<(f64, f64)> = numbers.chunks_exact(2).map(|c| (c[0], c[1])).collect();
    if pairs.windows(2).any(|w| w[1].0 <= w[0].0) {
        return Err("the wavelengths must increase".into());
    }
    Ok(pairs)
}

/// An unbounded value (η or k given as rgb or samples), per channel.
pub fn unbounded(s: &Spectrum) -> Result<[f32; 3], String> {
    match s {
        Spectrum::Rgb(rgb) => non_negative(*rgb),
        Spectrum::Sampled(samples) => Ok(sampled_to_rgb(samples, SpectrumRole::Unbounded).0),
        _ => Err("expected an rgb value or wavelength–value pairs here".into()),
    }
}

fn non_negative(rgb: [f32; 3]) -> Result<[f32; 3], String> {
    if rgb.iter().all(|c| c.is_finite() && *c >= 0.0) {
        Ok(rgb)
    } else {
        Err(format!("colour values must be finite and ≥ 0, got {rgb:?}"))
    }
}

/// Planck's law (the constant factor left out: only the curve's shape matters here).
fn planck(lambda_nm: f64, kelvin: f64) -> f64 {
    const HC_OVER_K: f64 = 1.438_776_877e-2; // m·K
    let lambda = lambda_nm * 1e-9;
    1.0 / (lambda.powi(5) * ((HC_OVER_K / (lambda * kelvin)).exp() - 1.0))
}

fn interpolate(samples: &[(f64, f64)], lambda: f64) -> f64 {
    let upper = samples.partition_point(|&(w, _)| w < lambda);
    match (upper, samples.get(upper)) {
        (0, Some(&(_, v))) => v,
        (_, None) => samples.last().map_or(0.0, |s| s.1),
        (i, Some(&(w1, v1))) => {
            let (w0, v0) = samples[i - 1];
            v0 + (lambda - w0) / (w1 - w0) * (v1 - v0)
        }
    }
}

/// The linear sRGB of a spectrum scaled to luminance Y = 1, integrated every nanometre over
/// 360–830 nm against the CIE 1931 observer.
fn unit_luminance(spectrum: impl Fn(f64) -> f64) -> [f32; 3] {
    let mut xyz = [0.0f64; 3];
    for nm in 360..=830 {
        let lambda = nm as f64;
        let s = spectrum(lambda);
        for (sum, table) in xyz.iter_mut().zip([&X_BAR, &Y_BAR, &Z_BAR]) {
            *sum += tabulated(table, lambda) * s;
        }
    }
    let [x, y, z] = xyz.map(|c| c / xyz[1]);
    [
        3.240479 * x - 1.537150 * y - 0.498535 * z,
        -0.969256 * x + 1.875991 * y + 0.041556 * z,
        0.055648 * x - 0.204043 * y + 1.057311 * z,
    ]
    .map(|c| c.max(0.0) as f32)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn luminance(rgb: [f32; 3]) -> f32 {
        0.2126 * rgb[0] + 0.7152 * rgb[1] + 0.0722 * rgb[2]
    }

    #[test]
    fn blackbodies_have_unit_luminance_and_redden_as_they_cool() {
        let warm = emission(&Spectrum::Blackbody(2700.0)).unwrap();
        let cool = emission(&Spectrum::Blackbody(10000.0)).unwrap();
        for rgb in [warm, cool] {
            assert!((luminance(rgb) - 1.0).abs() < 0.01, "{rgb:?}");
        }
        assert!(warm[0] > warm[1] && warm[1] > warm[2], "{warm:?}");
        assert!(cool[2] > cool[0], "{cool:?}");
        // About 6500 K is white in sRGB (D65's correlated temperature is 6504 K; the
        // blackbody lies a little off the daylight locus).
        let white = emission(&Spectrum::Blackbody(6504.0)).unwrap();
        assert!(white.iter().all(|c| (c - 1.0).abs() < 0.1), "{white:?}");
    }

    #[test]
    fn a_flat_spectrum_as_a_light_is_neutral_at_unit_luminance() {
        // An equal-energy spectrum (illuminant E) is slightly pink in sRGB, at Y = 1.
        let e = emission(&Spectrum::Sampled(vec![(300.0, 5.0), (900.0, 5.0)])).unwrap();
        assert!((luminance(e) - 1.0).abs() < 0.01, "{e:?}");
        assert!(e[0] > 1.0 && e[2] < 1.1 && e[1] < 1.0, "{e:?}");
    }

    #[test]
    fn named_spectra_map_to_glint_values_or_are_refused_by_name() {
        assert_eq!(metal("metal-Au-eta", "metal-Au-k"), Ok("Au"));
        assert!(metal("metal-Au-eta", "metal-Cu-k").unwrap_err().contains("both of one metal"));
        assert!(metal("metal-TiO2-eta", "metal-TiO2-k").unwrap_err().contains("TiO2"));
        assert_eq!(index(&Spectrum::Named("glass-BK7".into())), Ok(1.5168));
        assert!(index(&Spectrum::Named("glass-XYZ".into())).unwrap_err().contains("glass-BK7"));
        // 1.6 − 0.2 · 87.6/200 at the d line.
        assert!((index(&Spectrum::Sampled(vec![(500.0, 1.6), (700.0, 1.4)])).unwrap() - 1.5124).abs() < 1e-6);
        assert!(emission(&Spectrum::Named("stdillum-F3".into())).unwrap_err().contains("stdillum-F3"));
        assert!(albedo(&Spectrum::Rgb([1.2, 0.0, 0.0])).is_err());
    }
}

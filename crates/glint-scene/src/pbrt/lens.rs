//! pbrt's `realistic` camera as the thin lens glint has: the lens system's paraxial focal
//! length from its element table, the film's distance from the focus distance, hence the field
//! of view; the aperture stop's diameter as the thin lens's.
//!
//! A lens file (pbrt's format) lists the interfaces from the scene's side to the film's, one
//! per line: curvature radius, thickness to the next (the last: to the film), index of
//! refraction after it (0 for air), aperture diameter; all in millimetres, a radius of 0 is
//! the aperture stop. What the thin lens leaves out: the system's thickness (principal
//! planes), aberrations, vignetting by the elements, and the exit pupil's size.

/// The paraxial focal length (mm) of a lens table.
pub fn focal_length(table: &str) -> Result<f64, String> {
    let mut elements = Vec::new();
    for (i, line) in table.lines().enumerate() {
        let line = line.split('#').next().unwrap_or("").trim();
        if line.is_empty() {
            continue;
        }
        let numbers: Vec<f64> = line
            .split_whitespace()
            .map(|w| w.parse::<f64>().map_err(|_| format!("line {}: `{w}` is not a number", i + 1)))
            .collect::<Result<_, _>>()?;
        let [radius, thickness, eta, _aperture] = numbers[..] else {
            return Err(format!("line {}: a lens element is 4 numbers (radius, thickness, index, aperture)", i + 1));
        };
        if !(radius.is_finite() && thickness.is_finite() && eta.is_finite() && eta >= 0.0) {
            return Err(format!("line {}: the element's numbers must be finite and its index ≥ 0", i + 1));
        }
        elements.push((radius, thickness, if eta == 0.0 { 1.0 } else { eta }));
    }
    if elements.is_empty() {
        return Err("the lens file lists no elements".into());
    }
    // A ray parallel to the axis at height 1, (height, index × angle), refracted at each
    // interface and carried to the next (not past the last: that is the film's distance).
    let (mut y, mut alpha, mut before) = (1.0f64, 0.0f64, 1.0f64);
    for (i, &(radius, thickness, after)) in elements.iter().enumerate() {
        if radius != 0.0 {
            alpha -= y * (after - before) / radius;
        }
        if i + 1 < elements.len() {
            y += thickness * alpha / after;
        }
        before = after;
    }
    if alpha.is_nan() || alpha >= 0.0 {
        return Err("the lens system does not converge light (its paraxial focal length is not positive)".into());
    }
    Ok(-1.0 / alpha)
}

/// The vertical field of view (degrees) across a film `height_mm` high, focused at
/// `focus_mm`, through a thin lens of focal length `focal_mm`: the film stands at the image
/// distance v = f·d / (d − f).
pub fn field_of_view(focal_mm: f64, focus_mm: f64, height_mm: f64) -> Result<f64, String> {
    if focus_mm <= focal_mm {
        return Err(format!("the focus distance ({focus_mm} mm) must be beyond the focal length ({focal_mm:.1} mm)"));
    }
    let image = focal_mm * focus_mm / (focus_mm - focal_mm);
    Ok(2.0 * (0.5 * height_mm / image).atan().to_degrees())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_thin_biconvex_lens_has_the_lensmakers_focal_length() {
        // 1/f = (n − 1)(1/R1 − 1/R2) = 0.5 · (1/100 + 1/100): f = 100 mm.
        let f = focal_length("# a thin lens\n100 0 1.5 20\n-100 98 0 20\n").unwrap();
        assert!((f - 100.0).abs() < 1e-9, "{f}");
        // A thick one: 1/f = (n − 1)[1/R1 − 1/R2 + (n − 1) t / (n R1 R2)].
        let f = focal_length("50 10 1.5 20\n-50 40 0 20\n").unwrap();
        let expected = 1.0 / (0.5 * (1.0 / 50.0 + 1.0 / 50.0 - 0.5 * 10.0 / (1.5 * 50.0 * 50.0)));
        assert!((f - expected).abs() < 1e-9, "{f} vs {expected}");
        // The aperture stop (radius 0) bends nothing.
        let with_stop = focal_length("100 0 1.5 20\n-100 5 0 20\n0 5 0 10\n").unwrap();
        assert!((with_stop - 100.0).abs() < 1e-9);
        assert!(focal_length("-100 0 1.5 20\n100 5 0 20\n").unwrap_err().contains("does not converge"));
        assert!(focal_length("1 2 3\n").unwrap_err().contains("line 1"));
    }

    #[test]
    fn the_field_of_view_follows_the_image_distance() {
        // Focused at infinity-ish, a 24 mm film behind 50 mm: 2·atan(12/50) = 26.99°.
        let fov = field_of_view(50.0, 1e9, 24.0).unwrap();
        assert!((fov - 26.9915).abs() < 1e-3, "{fov}");
        // Focused at 1 m the film moves back to 52.63 mm: a narrower view.
        assert!(field_of_view(50.0, 1000.0, 24.0).unwrap() < fov);
        assert!(field_of_view(50.0, 40.0, 24.0).is_err());
    }
}

//! Chi-square goodness-of-fit test of a direction-sampling routine against its pdf (after
//! Mitsuba 3's `chi2.py` and pbrt-v4's `bsdfs_test.cpp`): samples are histogrammed over the
//! sphere in cells of equal solid angle (cos θ × φ), the expected count of each cell is its
//! pdf integrated by a fine midpoint rule, cells expecting fewer than 5 samples are pooled,
//! and the statistic's p-value comes from the regularized incomplete gamma function.

use std::f64::consts::PI;

use glam::{Vec2, Vec3};

use super::Rng;

#[derive(Debug)]
pub struct Chi2Result {
    pub p_value: f64,
    pub statistic: f64,
    pub degrees_of_freedom: usize,
}

/// `sample(u)` draws a direction from two uniform numbers (`None` = no sample); `pdf(w)` is its
/// density per solid angle. Odd bin counts keep cell edges off symmetry planes.
pub fn chi2_test(
    sample: impl FnMut(Vec2) -> Option<Vec3>,
    pdf: impl Fn(Vec3) -> f64,
    samples: usize,
    cos_bins: usize,
    phi_bins: usize,
    seed: u64,
) -> Chi2Result {
    chi2_test_with_resolution(sample, pdf, samples, cos_bins, phi_bins, seed, 8)
}

/// `chi2_test` integrating each cell's pdf on `sub × sub` points: finer for pdfs with sharp
/// edges inside cells (a light's outline), whose partly covered cells must not come out empty.
pub fn chi2_test_with_resolution(
    mut sample: impl FnMut(Vec2) -> Option<Vec3>,
    pdf: impl Fn(Vec3) -> f64,
    samples: usize,
    cos_bins: usize,
    phi_bins: usize,
    seed: u64,
    sub: usize,
) -> Chi2Result {
    let cell = |w: Vec3| -> usize {
        let c = (((w.z as f64 + 1.0) * 0.5 * cos_bins as f64) as usize).min(cos_bins - 1);
        let phi = (w.y as f64).atan2(w.x as f64).rem_euclid(2.0 * PI);
        let p = ((phi / (2.0 * PI) * phi_bins as f64) as usize).min(phi_bins - 1);
        c * phi_bins + p
    };
    let mut observed = vec![0.0f64; cos_bins * phi_bins];
    let mut rng = Rng::new(seed, 17);
    for _ in 0..samples {
        if let Some(w) = sample(Vec2::new(rng.next_f32(), rng.next_f32())) {
            observed[cell(w.normalize())] += 1.0;
        }
    }
    // Expected counts: integrate the pdf over each cell (uniform in cos θ and φ, so the
    // solid-angle measure of a sub-cell is its area in (cos θ, φ)).
    let sub_cells = sub;
    let mut expected = vec![0.0f64; cos_bins * phi_bins];
    for c in 0..cos_bins {
        for p in 0..phi_bins {
            let mut integral = 0.0;
            for i in 0..sub_cells {
                let z = -1.0 + 2.0 * (c as f64 + (i as f64 + 0.5) / sub_cells as f64) / cos_bins as f64;
                for j in 0..sub_cells {
                    let phi = 2.0 * PI * (p as f64 + (j as f64 + 0.5) / sub_cells as f64) / phi_bins as f64;
                    let r = (1.0 - z * z).max(0.0).sqrt();
                    integral += pdf(Vec3::new((r * phi.cos()) as f32, (r * phi.sin()) as f32, z as f32));
                }
            }
            let measure = (2.0 / cos_bins as f64) * (2.0 * PI / phi_bins as f64) / (sub_cells * sub_cells) as f64;
            expected[c * phi_bins + p] = integral * measure * samples as f64;
        }
    }
    // Pool sparse cells, smallest first, into one bucket.
    let mut order: Vec<usize> = (0..expected.len()).collect();
    order.sort_by(|&a, &b| expected[a].total_cmp(&expected[b]));
    let (mut pooled_e, mut pooled_o, mut statistic, mut dof) = (0.0, 0.0, 0.0, 0usize);
    for &i in &order {
        if expected[i] == 0.0 {
            // Any sample where the pdf is zero is an outright failure.
            if observed[i] > 0.0 {
                return Chi2Result { p_value: 0.0, statistic: f64::INFINITY, degrees_of_freedom: 0 };
            }
        } else if expected[i] < 5.0 || pooled_e > 0.0 && pooled_e < 5.0 {
            pooled_e += expected[i];
            pooled_o += observed[i];
        } else {
            statistic += (observed[i] - expected[i]).powi(2) / expected[i];
            dof += 1;
        }
    }
    if pooled_e > 0.0 {
        statistic += (pooled_o - pooled_e).powi(2) / pooled_e;
        dof += 1;
    }
    let dof = dof.saturating_sub(1).max(1);
    Chi2Result { p_value: gamma_q(dof as f64 / 2.0, statistic / 2.0), statistic, degrees_of_freedom: dof }
}

/// ln Γ(x) by Lanczos' approximation (g = 7, 9 terms).
fn ln_gamma(x: f64) -> f64 {
    const C: [f64; 9] = [
        0.999_999_999_999_809_9,
        676.520_368_121_885_1,
        -1_259.139_216_722_402_8,
        771.323_428_777_653_1,
        -176.615_029_162_140_6,
        12.507_343_278_686_905,
        -0.138_571_095_265_720_12,
        9.984_369_578_019_572e-6,
        1.505_632_735_149_311_6e-7,
    ];
    let x = x - 1.0;
    let t = x + 7.5;
    let series = C[1..].iter().enumerate().fold(C[0], |acc, (i, c)| acc + c / (x + i as f64 + 1.0));
    0.5 * (2.0 * PI).ln() + (x + 0.5) * t.ln() - t + series.ln()
}

/// Regularized upper incomplete gamma Q(a, x) (Numerical Recipes §6.2: series below a + 1,
/// continued fraction above).
pub fn gamma_q(a: f64, x: f64) -> f64 {
    if x <= 0.0 {
        return 1.0;
    }
    if x < a + 1.0 {
        let (mut sum, mut term, mut n) = (1.0 / a, 1.0 / a, a);
        for _ in 0..1000 {
            n += 1.0;
            term *= x / n;
            sum += term;
            if term.abs() < sum.abs() * 1e-15 {
                break;
            }
        }
        1.0 - sum * (-x + a * x.ln() - ln_gamma(a)).exp()
    } else {
        let tiny = 1e-300;
        let mut b = x + 1.0 - a;
        let mut c = 1.0 / tiny;
        let mut d = 1.0 / b;
        let mut h = d;
        for i in 1..1000 {
            let an = -(i as f64) * (i as f64 - a);
            b += 2.0;
            d = an * d + b;
            if d.abs() < tiny {
                d = tiny;
            }
            c = b + an / c;
            if c.abs() < tiny {
                c = tiny;
            }
            d = 1.0 / d;
            let delta = d * c;
            h *= delta;
            if (delta - 1.0).abs() < 1e-15 {
                break;
            }
        }
        (-x + a * x.ln() - ln_gamma(a)).exp() * h
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::warp::*;

    #[test]
    fn incomplete_gamma_by_known_values() {
        // Q(1, x) = e^-x; chi-square with 2 dof at 5.991 has p = 0.05.
        assert!((gamma_q(1.0, 2.0) - (-2.0f64).exp()).abs() < 1e-10);
        assert!((gamma_q(1.0, 5.991 / 2.0) - 0.05).abs() < 1e-4);
        // 10 dof at 23.209: p = 0.01.
        assert!((gamma_q(5.0, 23.209 / 2.0) - 0.01).abs() < 1e-4);
        assert!((ln_gamma(5.0) - 24f64.ln()).abs() < 1e-10);
    }

    #[test]
    fn cosine_hemisphere_sampling_matches_its_pdf() {
        let r = chi2_test(
            |u| Some(square_to_cosine_hemisphere(u)),
            |w| cosine_hemisphere_pdf(w) as f64,
            500_000,
            21,
            41,
            1,
        );
        assert!(r.p_value > 0.01 / 4.0, "p = {} (chi2 {} with {} dof)", r.p_value, r.statistic, r.degrees_of_freedom);
    }

    #[test]
    fn uniform_sphere_sampling_matches_its_pdf() {
        let r = chi2_test(|u| Some(square_to_uniform_sphere(u)), |_| UNIFORM_SPHERE_PDF as f64, 500_000, 21, 41, 2);
        assert!(r.p_value > 0.01 / 4.0, "p = {}", r.p_value);
    }

    /// The test can fail: sampling the cosine lobe against the uniform-hemisphere pdf is caught.
    #[test]
    fn a_wrong_pdf_is_rejected() {
        let r = chi2_test(
            |u| Some(square_to_cosine_hemisphere(u)),
            |w| if w.z > 0.0 { 1.0 / (2.0 * PI) } else { 0.0 },
            200_000,
            21,
            41,
            3,
        );
        assert!(r.p_value < 1e-6, "p = {}", r.p_value);
    }
}

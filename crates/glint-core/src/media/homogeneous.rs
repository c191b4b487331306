//! A homogeneous medium: absorption σ_a and scattering σ_s per colour channel, the same
//! everywhere. Transmittance over a distance t is Beer–Lambert's exp(−σ_t t), σ_t = σ_a + σ_s.
//!
//! Free-flight distances are drawn as pbrt-v4 and Mitsuba's `volpathmis` draw them: a channel
//! chosen uniformly, t from its exponential, and the density of t the mean over the channels
//! of σ_t,c exp(−σ_t,c t) (one-sample MIS over the channels), so a medium whose channels
//! differ is sampled without bias and with bounded weights.

use crate::Rgb;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Homogeneous {
    pub sigma_a: Rgb,
    pub sigma_s: Rgb,
}

/// Where a free flight ends and the weight that event carries.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Flight {
    /// A real collision at distance `t`, with `weight` = transmittance / density of t (per
    /// channel): times σ_s there it is the path's scattering weight, times σ_t the power a
    /// photon brings there, times the medium's emission the light emitted along the way.
    Scattered { t: f32, weight: Rgb },
    /// Reached the end of the segment (`t_max`) unscattered: weight transmittance / P(this).
    Passed { weight: Rgb },
}

impl Homogeneous {
    pub fn sigma_t(&self) -> Rgb {
        self.sigma_a + self.sigma_s
    }

    /// exp(−σ_t t) per channel (an infinite distance transmits only where σ_t is 0).
    pub fn transmittance(&self, t: f32) -> Rgb {
        let s = self.sigma_t() * t;
        let channel = |x: f32| if x.is_nan() { 1.0 } else { (-x).exp() };
        Rgb::new(channel(s.x), channel(s.y), channel(s.z))
    }

    /// A free flight along a segment of length `t_max` (infinite for none): `u_channel`
    /// picks the channel, `u` the distance.
    pub fn sample_flight(&self, t_max: f32, u_channel: f32, u: f32) -> Flight {
        let sigma_t = self.sigma_t();
        let channel = ((u_channel * 3.0) as usize).min(2);
        let sigma = sigma_t[channel];
        let t = if sigma > 0.0 { -(1.0 - u).max(f32::MIN_POSITIVE).ln() / sigma } else { f32::INFINITY };
        if t < t_max {
            let transmittance = self.transmittance(t);
            let density = (sigma_t * transmittance).element_sum() / 3.0;
            Flight::Scattered { t, weight: transmittance / density }
        } else {
            let transmittance = self.transmittance(t_max);
            let probability = transmittance.element_sum() / 3.0;
            Flight::Passed { weight: transmittance / probability }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Rng;

    #[test]
    fn beer_lambert_through_a_slab_is_exact() {
        // σ_t = (0.5, 1, 2) over 3 units: e^{−1.5}, e^{−3}, e^{−6}.
        let medium = Homogeneous { sigma_a: Rgb::new(0.2, 0.5, 1.5), sigma_s: Rgb::new(0.3, 0.5, 0.5) };
        let t = medium.transmittance(3.0);
        let expected = Rgb::new((-1.5f32).exp(), (-3.0f32).exp(), (-6.0f32).exp());
        assert!((t - expected).abs().max_element() < 1e-7, "{t} vs {expected}");
        // Two slabs in a row transmit the product: Beer–Lambert's law is multiplicative.
        let halves = medium.transmittance(1.2) * medium.transmittance(1.8);
        assert!((halves - t).abs().max_element() < 1e-7);
    }

    /// The flight's estimates are unbiased, per channel: E[weight · 1(passed)] is the
    /// segment's transmittance, and E[weight · 1(scattered)] the single-scattering integral
    /// ∫₀^T σ_s e^{−σ_t t} dt = σ_s / σ_t · (1 − e^{−σ_t T}), with channels as unequal as 1 : 8.
    #[test]
    fn free_flights_estimate_transmittance_and_scattering_without_bias() {
        let medium = Homogeneous { sigma_a: Rgb::new(0.1, 0.4, 1.0), sigma_s: Rgb::new(0.15, 0.6, 1.0) };
        let t_max = 1.5;
        let mut rng = Rng::new(17, 1);
        let n = 400_000;
        let (mut passed, mut scattered) = (Rgb::ZERO, Rgb::ZERO);
        let (mut passed2, mut scattered2) = (Rgb::ZERO, Rgb::ZERO);
        for _ in 0..n {
            match medium.sample_flight(t_max, rng.next_f32(), rng.next_f32()) {
                Flight::Passed { weight } => {
                    passed += weight;
                    passed2 += weight * weight;
                }
                Flight::Scattered { weight, t } => {
                    assert!(t < t_max);
                    let weight = weight * medium.sigma_s;
                    scattered += weight;
                    scattered2 += weight * weight;
                }
            }
        }
        let sigma_t = medium.sigma_t();
        let expected_pass = medium.transmittance(t_max);
        let expected_scatter = medium.sigma_s / sigma_t * (Rgb::ONE - expected_pass);
        for c in 0..3 {
            for (sum, sum2, expected) in [(passed, passed2, expected_pass), (scattered, scattered2, expected_scatter)] {
                let mean = sum[c] as f64 / n as f64;
                let error = ((sum2[c] as f64 / n as f64 - mean * mean) / n as f64).sqrt();
                assert!(
                    (mean - expected[c] as f64).abs() < 4.0 * error + 1e-6,
                    "channel {c}: {mean} vs {} (± {error})",
                    expected[c]
                );
            }
        }
    }

    #[test]
    fn an_empty_medium_never_scatters_and_a_flight_without_end_always_does() {
        let vacuum = Homogeneous { sigma_a: Rgb::ZERO, sigma_s: Rgb::ZERO };
        assert_eq!(vacuum.sample_flight(10.0, 0.5, 0.9), Flight::Passed { weight: Rgb::ONE });
        let fog = Homogeneous { sigma_a: Rgb::ZERO, sigma_s: Rgb::ONE };
        match fog.sample_flight(f32::INFINITY, 0.2, 0.999_999) {
            // A lossless medium scatters with weight 1 (σ_s = σ_t, one channel).
            Flight::Scattered { weight, .. } => {
                assert!((weight * fog.sigma_s - Rgb::ONE).abs().max_element() < 1e-5)
            }
            other => panic!("{other:?}"),
        }
    }
}

//! The limits a render is held to, whichever front end asks for it: `glint render` and the
//! Python module's `Scene.render` call these same checks, so they refuse the same renders
//! with the same words.
//!
//! - **Memory**: a render whose own buffers (film, image, photon maps, SPPM's per-pixel
//!   state) would need more than the limit is refused before any work. The limit is
//!   `--memory-limit GIB`, else the environment variable `GLINT_MEMORY_LIMIT` (GiB), else
//!   8 GiB; the scene readers hold the files they read to it too (`glint_scene::set_memory_limit`).
//! - **Threads**: a render runs on 1 to [`MAX_THREADS`] worker threads (asking for a hundred
//!   thousand made the Python module spawn them until the machine gave out).

use glint_core::integrators::{IntegratorKind, IntegratorSettings};

use crate::error::CliError;

/// The most worker threads a render may ask for.
pub const MAX_THREADS: usize = 1024;

const GIB: f64 = (1u64 << 30) as f64;

/// The memory limit when neither `--memory-limit` nor GLINT_MEMORY_LIMIT sets one, in GiB.
pub const DEFAULT_MEMORY_LIMIT_GIB: f64 = 8.0;

/// A requested number of worker threads, checked: 1 to [`MAX_THREADS`].
pub fn thread_count(requested: i128) -> Result<usize, String> {
    if (1..=MAX_THREADS as i128).contains(&requested) {
        Ok(requested as usize)
    } else {
        Err(format!("the number of worker threads must be from 1 to {MAX_THREADS}, got {requested}"))
    }
}

/// [`thread_count`] from text (`--threads`).
pub fn parse_thread_count(text: &str) -> Result<usize, String> {
    let requested = text.trim().parse::<i128>().map_err(|_| {
        format!("the number of worker threads must be a whole number from 1 to {MAX_THREADS}, got `{text}`")
    })?;
    thread_count(requested)
}

/// The memory limit in bytes: `flag` (`--memory-limit`), else GLINT_MEMORY_LIMIT, else the
/// default (all in GiB).
pub fn memory_limit_bytes(flag: Option<f64>) -> Result<u64, CliError> {
    let (value, from) = match (flag, std::env::var("GLINT_MEMORY_LIMIT")) {
        (Some(v), _) => (v, "--memory-limit"),
        (None, Ok(text)) => (
            text.trim()
                .parse::<f64>()
                .map_err(|_| CliError::Setting(format!("GLINT_MEMORY_LIMIT must be a number of GiB, got `{text}`")))?,
            "GLINT_MEMORY_LIMIT",
        ),
        (None, Err(_)) => (DEFAULT_MEMORY_LIMIT_GIB, "the default"),
    };
    if !(value.is_finite() && value > 0.0) {
        return Err(CliError::Setting(format!("{from} must be a positive number of GiB, got {value}")));
    }
    Ok((value * GIB).min(u64::MAX as f64) as u64)
}

/// About how much memory a render's own buffers take: the film (sums, weights) and the image
/// made from it, the per-pixel state of SPPM and light tracing, and photon maps.
pub fn memory_needed(kind: IntegratorKind, settings: &IntegratorSettings, width: u32, height: u32) -> u64 {
    let pixels = u64::from(width) * u64::from(height);
    // Film sums and weights (16 bytes), the RGB image (12) and its encoded file (up to 12).
    let mut bytes = pixels * 40;
    bytes += match kind {
        // Each pass: a visible point (~200 bytes with its BSDF) and state (32) per pixel, and
        // as many photons (32 bytes, with the kd-tree's copy).
        IntegratorKind::Sppm => pixels * 300 + u64::from(settings.photons_per_pass) * 96,
        // A pass's splats: a few per pixel.
        IntegratorKind::Light => pixels * 64,
        IntegratorKind::Photon => {
            let photons = u64::from(settings.photon.global_photons) + u64::from(settings.photon.caustic_photons);
            photons * 96
        }
        IntegratorKind::VolPhoton => u64::from(settings.photon.global_photons) * 96,
        _ => 0,
    };
    bytes
}

/// Refuses a render whose own buffers would not fit `memory_limit` bytes.
pub fn check_memory(
    kind: IntegratorKind,
    settings: &IntegratorSettings,
    width: u32,
    height: u32,
    memory_limit: u64,
) -> Result<(), CliError> {
    let needed = memory_needed(kind, settings, width, height);
    if needed > memory_limit {
        return Err(CliError::TooLarge(format!(
            "this render needs about {} ({width}x{height} pixels{}), more than the memory limit of {}; raise it with --memory-limit GIB (or GLINT_MEMORY_LIMIT), or render smaller",
            glint_scene::describe_bytes(needed),
            if matches!(kind, IntegratorKind::Photon | IntegratorKind::VolPhoton) { " and the photon maps" } else { "" },
            glint_scene::describe_bytes(memory_limit)
        )));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn thread_counts_from_one_to_the_bound() {
        assert_eq!(thread_count(1), Ok(1));
        assert_eq!(thread_count(MAX_THREADS as i128), Ok(MAX_THREADS));
        for refused in [0, -1, MAX_THREADS as i128 + 1, 100_000] {
            let message = thread_count(refused).unwrap_err();
            assert!(message.contains("from 1 to 1024") && message.ends_with(&refused.to_string()), "{message}");
        }
        assert_eq!(parse_thread_count("8"), Ok(8));
        assert!(parse_thread_count("eight").unwrap_err().contains("whole number"));
        assert!(parse_thread_count("100000").unwrap_err().contains("got 100000"));
    }

    #[test]
    fn the_estimate_counts_pixels_and_photons() {
        let settings = IntegratorSettings::default();
        assert_eq!(memory_needed(IntegratorKind::Path, &settings, 16384, 16384), 16384 * 16384 * 40);
        let mut photons = settings;
        photons.photon.global_photons = 1_000_000;
        photons.photon.caustic_photons = 0;
        assert_eq!(memory_needed(IntegratorKind::Photon, &photons, 1, 1), 40 + 96_000_000);
        let refused = check_memory(IntegratorKind::Path, &settings, 16384, 16384, 8 << 30).unwrap_err().to_string();
        assert!(refused.starts_with("this render needs about 10.0 GiB (16384x16384 pixels)"), "{refused}");
        assert!(refused.contains("memory limit of 8.0 GiB") && refused.contains("--memory-limit"), "{refused}");
        assert!(check_memory(IntegratorKind::Path, &settings, 1024, 1024, 8 << 30).is_ok());
    }
}

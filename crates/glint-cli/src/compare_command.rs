//! `glint compare IMAGE REFERENCE`: error metrics, ꟻLIP (HDR, or LDR at an exposure) and the Z-test of an image against a
//! reference (`glint_cli::compare`), as text or JSON, and the ꟻLIP error map as an image.

use std::path::PathBuf;

use clap::Args;
use glint_cli::compare::{self, Metrics};
use glint_cli::error::CliError;
use glint_cli::output::write_file_atomically;

#[derive(Args)]
pub struct CompareArgs {
    /// The image to judge (.exr, .pfm, .hdr: linear; .png, .jpg: sRGB-decoded).
    image: PathBuf,
    /// The reference it should equal.
    reference: PathBuf,
    /// The reference's per-sample variance (as Mitsuba's references have): adds the per-pixel
    /// Z-test of the image at its sample count.
    #[arg(long, value_name = "VAR")]
    variance: Option<PathBuf>,
    /// The image's samples per pixel for the Z-test (default: its EXR header's `glint:spp`).
    #[arg(long)]
    spp: Option<u64>,
    /// LDR-ꟻLIP at this exposure (stops; the images as 8-bit sRGB) instead of HDR-ꟻLIP, which
    /// looks at the range of exposures the reference spans.
    #[arg(long, allow_hyphen_values = true)]
    exposure: Option<f32>,
    /// Write ꟻLIP's error map here, in the magma colours (.png).
    #[arg(long, value_name = "FILE")]
    error_image: Option<PathBuf>,
    /// Print the results as JSON.
    #[arg(long)]
    json: bool,
}

pub fn run(args: CompareArgs) -> Result<(), CliError> {
    // What an image's header may declare (GLINT_MEMORY_LIMIT, as for `render`).
    glint_cli::job::memory_limit(None)?;
    let read = |path: &PathBuf| compare::read_image(path).map_err(CliError::Input);
    let (image, reference) = (read(&args.image)?, read(&args.reference)?);
    let warnings = compare::warnings(&args.image, &image, &args.reference, &reference);
    let metrics = compare::metrics(&image, &reference).map_err(CliError::Input)?;
    let flip = match args.exposure {
        Some(exposure) => compare::flip(&image, &reference, exposure),
        None => compare::hdr_flip(&image, &reference),
    }
    .map_err(CliError::Input)?;
    let kind = if args.exposure.is_some() { "ldr" } else { "hdr" };
    let z_test = match &args.variance {
        None => None,
        Some(path) => {
            let spp = match args.spp {
                Some(n) => n,
                None => image.attributes.get("glint:spp").and_then(|s| s.parse().ok()).ok_or_else(|| {
                    CliError::Setting(format!(
                        "--variance: `{}` does not say its sample count (no `glint:spp` in its header): give --spp",
                        args.image.display()
                    ))
                })?,
            };
            let z = compare::z_test(&image, &reference, &read(path)?, spp).map_err(CliError::Input)?;
            Some((spp, z))
        }
    };
    if let Some(path) = &args.error_image {
        let png = image::RgbImage::from_raw(image.width, image.height, flip.map.clone())
            .ok_or_else(|| CliError::Input("the ꟻLIP map has the wrong size".into()))?;
        let mut bytes = Vec::new();
        png.write_to(&mut std::io::Cursor::new(&mut bytes), image::ImageFormat::Png)
            .map_err(|e| CliError::Input(format!("cannot encode `{}`: {e}", path.display())))?;
        write_file_atomically(path, &bytes, "output")?;
    }
    if args.json {
        let z = z_test.map(|(spp, z)| {
            serde_json::json!({ "spp": spp, "fraction_passed": z.fraction, "passed": z.passed, "alpha": z.alpha })
        });
        let document = serde_json::json!({
            "image": args.image.display().to_string(),
            "reference": args.reference.display().to_string(),
            "mse": metrics.mse, "rel_mse": metrics.rel_mse, "mae": metrics.mae, "mean_ratio": metrics.mean_ratio,
            "mse_mean": Metrics::mean(metrics.mse), "rel_mse_mean": Metrics::mean(metrics.rel_mse),
            "mae_mean": Metrics::mean(metrics.mae),
            "flip": {
                "mean": flip.mean, "kind": kind, "exposures": flip.exposures,
                "pixels_per_degree": compare::FLIP_PIXELS_PER_DEGREE,
            },
            "z_test": z,
            "non_finite_pixels": {
                "image": metrics.non_finite.image, "reference": metrics.non_finite.reference,
                "left_out": metrics.non_finite.either,
            },
            "warnings": warnings,
        });
        println!("{}", serde_json::to_string_pretty(&document).unwrap_or_default());
        return Ok(());
    }
    for warning in &warnings {
        eprintln!("warning: {warning}");
    }
    let row = |name: &str, v: [f64; 3], mean: Option<f64>| {
        let mean = mean.map_or(String::new(), |m| format!("   mean {m:.6e}"));
        println!("{name:<11} R {:.6e}   G {:.6e}   B {:.6e}{mean}", v[0], v[1], v[2]);
    };
    let left_out = match metrics.non_finite.either {
        0 => String::new(),
        n => format!(", {n} non-finite pixels left out"),
    };
    println!(
        "{} against {} ({}x{}{left_out}):",
        args.image.display(),
        args.reference.display(),
        image.width,
        image.height
    );
    row("MSE", metrics.mse, Some(Metrics::mean(metrics.mse)));
    row("relMSE", metrics.rel_mse, Some(Metrics::mean(metrics.rel_mse)));
    row("MAE", metrics.mae, Some(Metrics::mean(metrics.mae)));
    row("mean ratio", metrics.mean_ratio, None);
    let (first, last) = (flip.exposures.first().copied().unwrap_or(0.0), flip.exposures.last().copied().unwrap_or(0.0));
    let seen = match args.exposure {
        Some(e) => format!("LDR-ꟻLIP at exposure {e}"),
        None => format!("HDR-ꟻLIP, {} exposures from {first:.2} to {last:.2} stops", flip.exposures.len()),
    };
    println!("FLIP        {:.6} ({seen}, {} pixels per degree)", flip.mean, compare::FLIP_PIXELS_PER_DEGREE);
    if let Some((spp, z)) = z_test {
        println!(
            "Z-test      {:.4} % of pixel channels pass at α = {:.3e} ({spp} spp): {}",
            100.0 * z.fraction,
            z.alpha,
            if z.passed { "PASS (≥ 99.75 %)" } else { "FAIL (< 99.75 %)" }
        );
    }
    Ok(())
}

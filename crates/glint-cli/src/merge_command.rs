//! `glint merge OUT PART…`: partial renders (`glint render --samples A..B`) combined into the
//! image one render of all their samples gives, bit for bit.

use std::path::PathBuf;

use clap::Args;
use glint_cli::error::CliError;
use glint_cli::output::check_writable;
use glint_cli::partial;

#[derive(Args)]
pub struct MergeArgs {
    /// The merged image: an EXR is itself a partial render (its header lists the samples it
    /// holds, so it can be merged further); PNG and PFM hold the image alone.
    output: PathBuf,
    /// The parts: EXR files written by `glint render --samples A..B` (or earlier merges) of
    /// one render, holding disjoint samples.
    #[arg(required = true)]
    parts: Vec<PathBuf>,
    /// No summary line.
    #[arg(short, long)]
    quiet: bool,
}

pub fn run(args: MergeArgs) -> Result<(), CliError> {
    // What a part's header may declare (GLINT_MEMORY_LIMIT, as for `render`).
    glint_cli::job::memory_limit(None)?;
    // Checked before the parts are read, so a bad name costs no work.
    check_writable(&args.output)?;
    let parts = args.parts.iter().map(|p| partial::read(p)).collect::<Result<Vec<_>, _>>()?;
    let count = parts.len();
    let partial::Merged { film, attributes, ranges } = partial::merge(parts)?;
    let attributes: Vec<(&str, String)> = attributes.iter().map(|(k, v)| (k.as_str(), v.clone())).collect();
    partial::write_as_named(&args.output, &film, &attributes)?;
    if !args.quiet {
        let samples: u32 = ranges.iter().map(|(a, b)| b - a).sum();
        say!(
            "merged {count} parts: samples {} ({samples} per pixel) -> {}",
            partial::format_ranges(&ranges),
            args.output.display()
        );
    }
    Ok(())
}

//! `glint`: the command-line renderer. Thin: it parses arguments, asks `glint-scene` for a
//! scene and `glint-core` for an image, and writes it.

/// `eprintln!` that never panics: a terminal that hung up (SIGHUP) or a closed pipe makes
/// writes to stderr fail, and a render must still write its image.
macro_rules! say {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        let _ = writeln!(std::io::stderr(), $($arg)*);
    }};
}

mod bench_rays_command;
mod compare_command;
mod explain_command;
mod merge_command;
mod render_command;

use std::process::ExitCode;

use clap::{Parser, Subcommand};

#[derive(Parser)]
#[command(name = "glint", version, about = "A CPU ray tracer for learning, teaching and research")]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Render a scene to an image (.png, .exr, .hdr or .pfm).
    #[command(
        after_help = "Exit status: 0 when the render ended (its samples done or its --time spent), 1 on an error (nothing is written, or what was written is named), 2 on a usage error, 3 when interrupted by Ctrl-C, SIGTERM or SIGHUP (the image and --checkpoint of the passes finished are written; if none had finished, nothing is, and the message says so), 130 on a second Ctrl-C (quit at once, nothing more written)."
    )]
    Render(render_command::RenderArgs),
    /// Explain one pixel: Whitted's ray tree (every ray, what it hit, each light's share and
    /// shadow test), or with --integrator the path tracers' and photon mapping's path, light
    /// tracing's particles or SPPM's gather; the lines add up to what `render --spp 1` gives.
    Explain(explain_command::ExplainArgs),
    /// Combine partial renders (`render --samples A..B`, EXR) into the image one render of all
    /// their samples gives, bit for bit; parts of different renders or with shared samples
    /// are refused.
    Merge(merge_command::MergeArgs),
    /// Compare an image with a reference: MSE, relMSE, MAE and the ratio of means per
    /// channel, ꟻLIP (and its error map), and with the reference's variance the per-pixel
    /// Z-test the project's tests use; as text or JSON.
    Compare(compare_command::CompareArgs),
    /// Benchmark the BVH on a mesh and a ray file (the Embree anchor's format): build time,
    /// closest-hit and any-hit Mrays/s, agreement with reference hits.
    BenchRays(bench_rays_command::BenchRaysArgs),
}

fn main() -> ExitCode {
    if let Some(message) = missing_cpu_features() {
        say!("glint: {message}");
        return ExitCode::FAILURE;
    }
    // A panic is a bug in glint, never the user's fault: say so in one line, without a backtrace.
    std::panic::set_hook(Box::new(|info| {
        // Output piped into a program that stopped reading (`| head`): end quietly, as Unix
        // tools do on SIGPIPE.
        if info.to_string().contains("Broken pipe") {
            std::process::exit(141);
        }
        say!("glint: internal error: {info}\nThis is a bug in glint; please report it with the scene that caused it.");
    }));
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Render(args) => render_command::run(args).map(|outcome| match outcome {
            render_command::Outcome::Finished => ExitCode::SUCCESS,
            render_command::Outcome::Interrupted => ExitCode::from(render_command::EXIT_INTERRUPTED),
        }),
        Command::Explain(args) => explain_command::run(args).map(|()| ExitCode::SUCCESS),
        Command::Compare(args) => compare_command::run(args).map(|()| ExitCode::SUCCESS),
        Command::Merge(args) => merge_command::run(args).map(|()| ExitCode::SUCCESS),
        Command::BenchRays(args) => bench_rays_command::run(args).map(|()| ExitCode::SUCCESS),
    };
    match result {
        Ok(code) => code,
        Err(message) => {
            say!("error: {message}");
            ExitCode::FAILURE
        }
    }
}

/// The CPU features this build was compiled for (`.cargo/config.toml`) that the CPU lacks,
/// as a message: such a binary would die of an illegal instruction somewhere in the render.
fn missing_cpu_features() -> Option<String> {
    #[cfg(all(target_arch = "x86_64", target_feature = "avx2"))]
    {
        let missing: Vec<&str> = [
            ("avx2", std::arch::is_x86_feature_detected!("avx2")),
            ("fma", std::arch::is_x86_feature_detected!("fma")),
        ]
        .into_iter()
        .filter_map(|(name, present)| (!present).then_some(name))
        .collect();
        if !missing.is_empty() {
            return Some(format!(
                "this build of glint needs a CPU with {}, which this one lacks; rebuild it with \
                 RUSTFLAGS=\"-C target-cpu=native\" (see README.md)",
                missing.join(" and ")
            ));
        }
    }
    None
}

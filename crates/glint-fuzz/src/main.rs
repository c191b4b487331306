//! `glint-fuzz TARGET`: feeds mutated inputs to one of glint's readers and stops at the first
//! input that makes it panic, run longer than `--hang-seconds`, or allocate more than
//! `--memory-mib` at once; such an input is written to `--findings` to be replayed
//! (`--replay FILE`). It runs on stable Rust, so CI can run it: mutations of the seed files in
//! `corpus/TARGET/` (bit flips, byte and block changes, splices, boundary numbers and the
//! format's own tokens), not coverage-guided like libFuzzer, and every new input that the
//! reader accepted is kept as a seed for further mutation while the run lasts.
//!
//! ```sh
//! cargo run --release -p glint-fuzz -- toml --seconds 60
//! cargo run --release -p glint-fuzz -- xml --execs 10000000
//! ```

mod allocator;
mod mutate;
mod targets;

use std::path::PathBuf;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use clap::Parser;

use targets::Target;

#[derive(Parser)]
#[command(name = "glint-fuzz", about = "Fuzz one of glint's readers on stable Rust")]
struct Args {
    /// What to fuzz.
    #[arg(value_enum)]
    target: Target,
    /// Stop after this many seconds (default: no time limit).
    #[arg(long)]
    seconds: Option<f64>,
    /// Stop after this many executions (default: no limit).
    #[arg(long)]
    execs: Option<u64>,
    /// The random stream of mutations.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// An input running longer than this is a hang.
    #[arg(long, default_value_t = 10.0)]
    hang_seconds: f64,
    /// An input allocating more than this many MiB at once is a finding.
    #[arg(long, default_value_t = 1024)]
    memory_mib: u64,
    /// Where a finding is written.
    #[arg(long, default_value = "fuzz-findings")]
    findings: PathBuf,
    /// Run one input (a finding) and report what it does.
    #[arg(long)]
    replay: Option<PathBuf>,
}

fn main() -> std::process::ExitCode {
    let args = Args::parse();
    let target = args.target;
    let scratch = std::env::temp_dir().join(format!("glint-fuzz-{}-{}", target.name(), std::process::id()));
    std::fs::create_dir_all(&scratch).expect("a scratch folder");
    // The readers' own memory limit, below the allocation bound checked here: an input that
    // slips past the limit is a finding.
    glint_scene::set_memory_limit((args.memory_mib << 20) / 4);
    let runner = targets::Runner::new(target, scratch.clone());
    if let Some(path) = &args.replay {
        let input = std::fs::read(path).expect("the input to replay");
        let outcome = std::panic::catch_unwind(|| runner.run(&input));
        println!("{}: {:?}; peak {} bytes", path.display(), outcome.map(|r| r.err()), allocator::peak_since_reset());
        return std::process::ExitCode::SUCCESS;
    }
    // No panic message per input: the fuzzer reports the one that matters.
    std::panic::set_hook(Box::new(|_| {}));
    let mut corpus = targets::seeds(target);
    assert!(!corpus.is_empty(), "no seed inputs in corpus/{}", target.name());
    let mut rng = mutate::Rng::new(args.seed);
    let started = Instant::now();
    let limit = args.seconds.map(Duration::from_secs_f64);
    let memory_limit = args.memory_mib << 20;

    // A watchdog: the current input and its start, in ms since `started`; a hang ends the
    // process after writing that input.
    let input_started = Arc::new(AtomicU64::new(u64::MAX));
    let current = Arc::new(Mutex::new(Vec::new()));
    {
        let (input_started, current) = (input_started.clone(), current.clone());
        let (hang, findings) = (args.hang_seconds, args.findings.clone());
        std::thread::spawn(move || loop {
            std::thread::sleep(Duration::from_millis(200));
            let at = input_started.load(Ordering::Relaxed);
            if at != u64::MAX && started.elapsed().as_millis() as u64 > at + (hang * 1000.0) as u64 {
                let _ = std::fs::create_dir_all(&findings);
                let kept = findings.join(format!("{}-hang", target.name()));
                // The main thread holds no lock while it runs an input.
                let _ = std::fs::write(&kept, &*current.lock().unwrap_or_else(|e| e.into_inner()));
                eprintln!("finding: an input ran longer than {hang} s; written to {}", kept.display());
                std::process::exit(1);
            }
        });
    }

    let (mut execs, mut accepted, mut peak) = (0u64, 0u64, 0usize);
    loop {
        if limit.is_some_and(|l| started.elapsed() >= l) || args.execs.is_some_and(|n| execs >= n) {
            break;
        }
        let mut input = mutate::mutate(&mut rng, &corpus, target.tokens());
        target.repair(&mut rng, &mut input);
        current.lock().unwrap_or_else(|e| e.into_inner()).clone_from(&input);
        allocator::reset_peak();
        input_started.store(started.elapsed().as_millis() as u64, Ordering::Relaxed);
        let outcome = std::panic::catch_unwind(|| runner.run(&input));
        input_started.store(u64::MAX, Ordering::Relaxed);
        execs += 1;
        let used = allocator::peak_since_reset();
        peak = peak.max(used);
        let finding = match &outcome {
            Err(_) => Some("panicked"),
            Ok(_) if used as u64 > memory_limit => Some("allocated beyond the memory bound"),
            _ => None,
        };
        if let Some(what) = finding {
            std::fs::create_dir_all(&args.findings).expect("the findings folder");
            let kept = args.findings.join(format!("{}-{execs}", target.name()));
            std::fs::write(&kept, &input).expect("the finding is written");
            eprintln!("finding after {execs} executions: an input {what}; written to {}", kept.display());
            let _ = std::fs::remove_dir_all(&scratch);
            return std::process::ExitCode::FAILURE;
        }
        if matches!(outcome, Ok(Ok(()))) {
            accepted += 1;
            // Accepted inputs are new shapes of valid input: mutate them too (bounded).
            if corpus.len() < 4096 && rng.below(16) == 0 {
                corpus.push(input);
            }
        }
        if execs % 1_000_000 == 0 {
            eprintln!("{}: {execs} executions, {:.0} s", target.name(), started.elapsed().as_secs_f64());
        }
    }
    let _ = std::fs::remove_dir_all(&scratch);
    let seconds = started.elapsed().as_secs_f64();
    println!(
        "{}: {execs} executions in {seconds:.1} s ({:.0}/s), {accepted} accepted, peak allocation {:.1} MiB, no panic, hang or allocation beyond {} MiB",
        target.name(),
        execs as f64 / seconds,
        peak as f64 / (1 << 20) as f64,
        args.memory_mib
    );
    std::process::ExitCode::SUCCESS
}

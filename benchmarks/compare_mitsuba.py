#!/usr/bin/env python3
"""glint's path tracer against Mitsuba 3 on the Cornell box, in one sitting (issue 5's speed
targets): samples per second and the error reached in equal time, as ratios.

Runs ../shared/anchors/mitsuba/bench.py for each Mitsuba configuration (a variant, and
optionally a sampler: `llvm_ad_rgb:multijitter`; the anchor's default is `independent`),
then the glint runs alternating, ROUNDS renders each: every `--glint` binary as it is, and
every `--variant` run (a binary with extra render arguments, say `--no-wavefront`). It
scores the first glint run's image for a few seeds against the converged reference with
the anchor's compare_exr.py, runs the first Mitsuba configuration once more (the host's
speed drifts), and prints one Markdown table. Standard library only; Mitsuba runs in its
own venv.

    python3 benchmarks/compare_mitsuba.py --mitsuba-python ~/venvs/mitsuba/bin/python \
        --glint target/release/glint [--glint /tmp/before-target/release/glint] \
        [--variant "target/release/glint:--no-wavefront"] \
        [--mitsuba llvm_ad_rgb scalar_rgb llvm_ad_rgb:multijitter] [--rounds 5] [--seeds 4]

Ratios are the first glint run against each Mitsuba configuration: best to best and median
to median (the last run of one that ran twice). Equal-time error = (relMSE × seconds) of
glint over the same product of the peer: below 1, glint's image is closer to the reference
after the same time. Build glint first: `cargo build --release`.

The host's speed drifts within a sitting (a Mitsuba run at its start and its end have differed
by 6 %), so `--paired N` then runs N rounds of the first Mitsuba configuration beside the
first glint run, each round one Mitsuba process (best of its three renders) and three glint
renders (best), in alternating order, and prints each round's ratio and their median: a
ratio of neighbours in time, which drift touches least.
"""
import argparse
import os
import re
import shlex
import statistics
import subprocess
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SHARED = os.path.join(ROOT, "..", "shared")
ANCHOR = os.path.join(SHARED, "anchors", "mitsuba")
SCENE = os.path.join(ROOT, "scenes", "cornell-box.toml")
REFERENCE = os.path.join(SHARED, "references", "cbox_256.exr")
SAMPLES = 256 * 256 * 64


def key_values(text):
    return dict(re.findall(r"(\w+)=([-+0-9.e]+)", text))


def mitsuba(python, configuration, threads):
    variant, _, sampler = configuration.partition(":")
    out = subprocess.run(
        [python, "bench.py", "cbox", "--res", "256", "--spp", "64", "--threads", str(threads),
         "--repeat", "3", "--variant", variant, "--sampler", sampler or "independent", "--ref", "auto"],
        cwd=ANCHOR, capture_output=True, text=True, check=True).stdout
    kv = key_values(out)
    return float(kv["render_s"]), float(kv["render_s_median"]), float(kv.get("relmse", "nan"))


def glint_seconds(binary, extra, threads, output):
    err = subprocess.run([binary, "render", SCENE, "--spp", "64", "--threads", str(threads), *extra, "-o", output],
                         capture_output=True, text=True, check=True).stderr
    # The summary line: "rendered WxH at N spp with INTEGRATOR in S s: ...".
    return float(re.search(r"^rendered .* in ([0-9.]+) s:", err, re.MULTILINE).group(1))


def glint_relmse(python, binary, extra, threads, seed, directory):
    image = os.path.join(directory, f"seed{seed}.pfm")
    subprocess.run([binary, "render", SCENE, "--spp", "64", "--threads", str(threads), "--seed", str(seed), *extra,
                    "-q", "-o", image], check=True)
    out = subprocess.run([python, os.path.join(ANCHOR, "compare_exr.py"), image, REFERENCE,
                          "--var", REFERENCE.replace(".exr", "_var.exr")],
                         capture_output=True, text=True, check=True).stdout
    return float(key_values(out)["relmse"])


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--mitsuba-python", required=True, help="the Python of a venv with mitsuba (anchor's setup.sh)")
    ap.add_argument("--glint", action="append", default=[], help="a glint binary (repeatable; the first is scored)")
    ap.add_argument("--variant", action="append", default=[],
                    help="BINARY:ARGS, a binary with extra render arguments, shell-quoted (repeatable)")
    ap.add_argument("--mitsuba", nargs="+", default=["llvm_ad_rgb", "scalar_rgb"],
                    help="Mitsuba variants, each optionally VARIANT:SAMPLER")
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--seeds", type=int, default=4)
    ap.add_argument("--paired", type=int, default=0, metavar="N",
                    help="then N rounds of the first Mitsuba configuration and the first glint run side by side")
    args = ap.parse_args()
    if not args.glint:
        ap.error("give at least one --glint binary (the first is the one scored)")
    runs = [(b, []) for b in args.glint]
    for variant in args.variant:
        binary, colon, extra = variant.partition(":")
        if not colon:
            ap.error(f"--variant {variant!r}: expected BINARY:ARGS")
        runs.append((binary, shlex.split(extra)))

    peers = {v: [mitsuba(args.mitsuba_python, v, args.threads)] for v in args.mitsuba}
    times = {i: [] for i in range(len(runs))}
    with tempfile.TemporaryDirectory() as directory:
        for _ in range(args.rounds):
            for i, (binary, extra) in enumerate(runs):
                times[i].append(glint_seconds(binary, extra, args.threads, os.path.join(directory, "t.pfm")))
        binary, extra = runs[0]
        errors = [glint_relmse(args.mitsuba_python, binary, extra, args.threads, seed, directory)
                  for seed in range(1, args.seeds + 1)]
    first = args.mitsuba[0]
    peers[first].append(mitsuba(args.mitsuba_python, first, args.threads))

    relmse = statistics.mean(errors)
    best, median = min(times[0]), statistics.median(times[0])
    print("| renderer | render s (best; median) | M samples/s (best) | relMSE at 64 spp | relMSE × s (best) | "
          "glint / peer: samples/s | equal-time error |")
    print("| --- | ---: | ---: | ---: | ---: | ---: | ---: |")
    for configuration, results in peers.items():
        p_best, p_median, p_relmse = results[-1]
        shown = "; ".join(f"{b:.2f}; {m:.2f}" for b, m, _ in results)
        print(f"| Mitsuba `{configuration}` | {shown} | {SAMPLES / p_best / 1e6:.2f} | {p_relmse:.6f} | "
              f"{p_relmse * p_best:.4f} | {p_best / best:.2f}; {p_median / median:.2f} | "
              f"{relmse * best / (p_relmse * p_best):.2f}; {relmse * median / (p_relmse * p_median):.2f} |")
    for i, (binary, extra) in enumerate(runs):
        label = " ".join([binary, *extra])
        error = f"{relmse:.6f} (seeds 1–{args.seeds}) | {relmse * best:.4f}" if i == 0 else " | "
        print(f"| glint `{label}` | {min(times[i]):.2f}; {statistics.median(times[i]):.2f} | "
              f"{SAMPLES / min(times[i]) / 1e6:.2f} | {error} | | |")
    if args.paired > 0:
        paired_rounds(args, first, runs[0])


def paired_rounds(args, configuration, run):
    """Rounds of Mitsuba's `configuration` and glint's `run` side by side: per round, Mitsuba's
    best of three renders over glint's best of three, Mitsuba first in odd rounds."""
    binary, extra = run
    ratios = []
    with tempfile.TemporaryDirectory() as directory:
        output = os.path.join(directory, "t.pfm")
        measure = {
            "mitsuba": lambda: mitsuba(args.mitsuba_python, configuration, args.threads)[0],
            "glint": lambda: min(glint_seconds(binary, extra, args.threads, output) for _ in range(3)),
        }
        for r in range(args.paired):
            order = ("mitsuba", "glint") if r % 2 == 0 else ("glint", "mitsuba")
            best = {name: measure[name]() for name in order}
            peer_best, glint_best = best["mitsuba"], best["glint"]
            ratios.append(peer_best / glint_best)
            print(f"paired round {r + 1}: Mitsuba `{configuration}` {peer_best:.3f} s, glint {glint_best:.3f} s, "
                  f"glint / peer samples/s {peer_best / glint_best:.3f}")
    print(f"paired rounds: glint / Mitsuba `{configuration}` samples/s median {statistics.median(ratios):.3f} "
          f"(min {min(ratios):.3f}, max {max(ratios):.3f}, {len(ratios)} rounds)")


if __name__ == "__main__":
    main()

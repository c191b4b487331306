//! `glint bench-rays MESH RAYS [--hits HITS]`: BVH build and ray throughput on a fixed ray set,
//! in the format of the Embree anchor (../shared/anchors/embree), so both are timed on exactly
//! the same rays and glint's hits are checked against Embree's.

use std::path::{Path, PathBuf};
use std::time::Instant;

use clap::Args;
use glint_cli::error::CliError;
use glint_core::accel::PrimitiveHit;
use glint_core::geometry::Ray;
use glint_core::scene::{Geometry, Object};
use glint_core::shapes::{IntersectMethods, Shape};
use glint_core::Vec3;
use rayon::prelude::*;

#[derive(Args)]
pub struct BenchRaysArgs {
    /// Mesh file (.ply, .ply.gz, .obj).
    mesh: PathBuf,
    /// Ray file: little-endian float32[N][8] = ox oy oz dx dy dz tmin tmax.
    rays: PathBuf,
    /// Reference hits to compare with: N × {float32 t, uint32 prim}, miss = (+inf, 0xFFFFFFFF).
    #[arg(long)]
    hits: Option<PathBuf>,
    /// Write glint's closest hits here, in the same format.
    #[arg(long)]
    out: Option<PathBuf>,
    /// Worker threads (default 1).
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..=1024))]
    threads: u32,
    /// Time each query this many times and report the best.
    #[arg(long, default_value_t = 3, value_parser = clap::value_parser!(u32).range(1..))]
    repeat: u32,
}

const MISS: u32 = u32::MAX;

pub fn run(args: BenchRaysArgs) -> Result<(), CliError> {
    let mesh = glint_scene::mesh::load_mesh(&args.mesh).map_err(CliError::Input)?;
    let triangles = mesh.triangle_count();
    let rays = read_rays(&args.rays).map_err(CliError::Input)?;
    if rays.is_empty() {
        return Err(CliError::Input(format!("the ray file `{}` holds no rays", args.rays.display())));
    }
    let pool = rayon::ThreadPoolBuilder::new().num_threads(args.threads as usize).build()?;

    let object = Object { name: "mesh".into(), shape: Shape::Mesh(mesh), transform: None, material: 0 };
    let geometry = pool.install(|| Geometry::new(vec![object], IntersectMethods::default()));
    let build_s = geometry.build_time().as_secs_f64();
    let stats = geometry.bvh_stats();
    println!(
        "mesh {}: {triangles} triangles; BVH built in {build_s:.3} s: binary {} nodes, {} leaves, depth {}, SAH cost {:.1}; 8-wide {} nodes, {} leaf blocks; {:.1} bytes/triangle (wide nodes + leaf records)",
        args.mesh.display(),
        stats.nodes,
        stats.leaves,
        stats.depth,
        stats.sah_cost,
        stats.wide_nodes,
        stats.leaf_blocks,
        stats.bytes as f64 / triangles as f64
    );
    println!("rays {}: {} rays, {} thread(s), best of {}", args.rays.display(), rays.len(), args.threads, args.repeat);

    let mut hits = Vec::new();
    // The same queries as a batch, several rays' traversals interleaved
    // (`Geometry::closest_primitives`).
    let mut interleaved_hits: Vec<(f32, u32)> = Vec::new();
    let interleaved_s = best_time(args.repeat, || {
        interleaved_hits = pool.install(|| {
            rays.par_chunks(4096)
                .flat_map_iter(|chunk| {
                    let mut chunk = chunk.to_vec();
                    let mut found = vec![PrimitiveHit::NONE; chunk.len()];
                    geometry.closest_primitives(&mut chunk, &mut found);
                    found.into_iter().map(|f| match f.object {
                        u32::MAX => (f32::INFINITY, MISS),
                        _ => (f.at.t, f.prim),
                    })
                })
                .collect()
        });
    });
    let closest_s = best_time(args.repeat, || {
        hits = pool.install(|| {
            rays.par_chunks(4096)
                .flat_map_iter(|chunk| {
                    chunk.iter().map(|ray| {
                        let mut r = *ray;
                        match geometry.closest_primitive(&mut r) {
                            Some(((_, prim), h)) => (h.t, prim),
                            None => (f32::INFINITY, MISS),
                        }
                    })
                })
                .collect()
        });
    });
    // The work behind those figures, outside the timed loop: what the heat map shows per pixel.
    let work = pool.install(|| {
        rays.par_iter()
            .map(|ray| geometry.traversal_counts(ray))
            .map(|c| (u64::from(c.nodes), u64::from(c.primitives)))
            .reduce(|| (0, 0), |a, b| (a.0 + b.0, a.1 + b.1))
    });
    println!(
        "closest-hit work: {:.1} nodes visited and {:.1} primitives tested per ray",
        work.0 as f64 / rays.len() as f64,
        work.1 as f64 / rays.len() as f64
    );
    let mut occluded = 0usize;
    let anyhit_s = best_time(args.repeat, || {
        occluded = pool.install(|| rays.par_iter().filter(|r| geometry.occluded(r)).count());
    });
    let n = rays.len() as f64;
    let same = |a: &(f32, u32), b: &(f32, u32)| a.0.to_bits() == b.0.to_bits() && a.1 == b.1;
    if let Some(k) = interleaved_hits.iter().zip(&hits).position(|(a, b)| !same(a, b)) {
        return Err(CliError::Input(format!(
            "ray {k}: the interleaved query found {:?}, the one-ray query {:?}",
            interleaved_hits[k], hits[k]
        )));
    }
    let hit_count = hits.iter().filter(|h| h.1 != MISS).count();
    println!("closest hit: {:.3} Mrays/s ({hit_count} hits)", n / closest_s / 1e6);
    println!(
        "closest hit, {} rays interleaved: {:.3} Mrays/s (the same hits)",
        glint_core::accel::INTERLEAVED_RAYS,
        n / interleaved_s / 1e6
    );
    println!("any hit:     {:.3} Mrays/s ({occluded} occluded)", n / anyhit_s / 1e6);
    if occluded != hit_count {
        println!("warning: any-hit found {occluded} occluded rays, closest hit {hit_count} hits");
    }

    if let Some(out) = &args.out {
        write_hits(out, &hits).map_err(CliError::Input)?;
    }
    let matches = match &args.hits {
        Some(path) => {
            let reference = read_hits(path).map_err(CliError::Input)?;
            if reference.len() != hits.len() {
                return Err(CliError::Input(format!(
                    "{}: {} hits for {} rays",
                    path.display(),
                    reference.len(),
                    hits.len()
                )));
            }
            let (same, report) = compare_hits(&reference, &hits);
            println!("{report}");
            format!("{same}/{}", hits.len())
        }
        None => "-".into(),
    };
    println!(
        "build_s={build_s:.4} closest_mrays={:.4} interleaved_mrays={:.4} anyhit_mrays={:.4} matches={matches}",
        n / closest_s / 1e6,
        n / interleaved_s / 1e6,
        n / anyhit_s / 1e6
    );
    Ok(())
}

fn best_time(repeat: u32, mut f: impl FnMut()) -> f64 {
    (0..repeat.max(1))
        .map(|_| {
            let start = Instant::now();
            f();
            start.elapsed().as_secs_f64()
        })
        .fold(f64::INFINITY, f64::min)
}

fn floats(path: &Path, record: usize) -> Result<Vec<[u8; 4]>, String> {
    let bytes = std::fs::read(path).map_err(|e| format!("cannot read `{}`: {e}", path.display()))?;
    if bytes.len() % (4 * record) != 0 {
        return Err(format!("`{}`: size {} is not a multiple of {} bytes", path.display(), bytes.len(), 4 * record));
    }
    Ok(bytes.chunks_exact(4).map(|c| [c[0], c[1], c[2], c[3]]).collect())
}

fn read_rays(path: &Path) -> Result<Vec<Ray>, String> {
    let words = floats(path, 8)?;
    Ok(words
        .chunks_exact(8)
        .map(|w| {
            let f: Vec<f32> = w.iter().map(|b| f32::from_le_bytes(*b)).collect();
            Ray::with_range(Vec3::new(f[0], f[1], f[2]), Vec3::new(f[3], f[4], f[5]), f[6], f[7])
        })
        .collect())
}

fn read_hits(path: &Path) -> Result<Vec<(f32, u32)>, String> {
    let words = floats(path, 2)?;
    Ok(words.chunks_exact(2).map(|w| (f32::from_le_bytes(w[0]), u32::from_le_bytes(w[1]))).collect())
}

fn write_hits(path: &Path, hits: &[(f32, u32)]) -> Result<(), String> {
    let bytes: Vec<u8> = hits.iter().flat_map(|(t, p)| t.to_le_bytes().into_iter().chain(p.to_le_bytes())).collect();
    std::fs::write(path, bytes).map_err(|e| format!("cannot write `{}`: {e}", path.display()))
}

/// Same rules as the anchor's check_hits.py: `same` = both miss, or the same primitive at t
/// within 1e-4 relative; `equiv` = another primitive at the same t (a shared edge or vertex).
fn compare_hits(reference: &[(f32, u32)], ours: &[(f32, u32)]) -> (usize, String) {
    let (mut same, mut equiv, mut t_off, mut hit_miss, mut other) = (0, 0, 0, 0, 0);
    for (&(tr, pr), &(t, p)) in reference.iter().zip(ours) {
        let close = (t - tr).abs() <= 1e-4 * tr.abs();
        match (pr == MISS, p == MISS) {
            (true, true) => same += 1,
            (true, false) | (false, true) => hit_miss += 1,
            _ if p == pr && close => same += 1,
            _ if p == pr => t_off += 1,
            _ if close => equiv += 1,
            _ => other += 1,
        }
    }
    let n = reference.len();
    let bad = t_off + hit_miss + other;
    let report = format!(
        "hits vs reference: same {same}, equiv {equiv}, bad {bad} (t_off {t_off}, hit_miss {hit_miss}, other {other}): {:.5} % agree",
        100.0 * (same + equiv) as f64 / n.max(1) as f64
    );
    (same + equiv, report)
}

//! Participating media through the native format and `volpath`: Beer–Lambert through a slab
//! (homogeneous and grid, grey and per channel, against the exact transmittance), the furnace
//! of a lossless medium under a uniform sky (radiance conserved), shadow rays through fog and
//! through thin sheets, and the format's errors.

use std::path::PathBuf;

use glint_core::integrators::IntegratorKind;
use glint_core::media::MediumKind;
use glint_core::render::{render, render_with, RenderSettings};
use glint_core::Rgb;
use glint_scene::load_scene;

fn scene(name: &str, text: &str, files: &[(&str, Vec<u8>)]) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("glint-media-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for (file, bytes) in files {
        std::fs::write(dir.join(file), bytes).unwrap();
    }
    let path = dir.join(format!("{name}.toml"));
    std::fs::write(&path, text).unwrap();
    path
}

/// The mean and the standard error of the mean of every pixel's value, per channel.
fn render_mean(path: &std::path::Path, spp: u32, seed: u64) -> (Rgb, Rgb) {
    let loaded = load_scene(path).unwrap_or_else(|e| panic!("{e}"));
    let integrator = loaded.render.integrator.create(&loaded.render.integrator_settings).unwrap();
    let settings = RenderSettings { spp, seed, filter: loaded.render.filter, sampler: loaded.render.sampler };
    let image = render(&loaded.scene, integrator.as_ref(), &settings, &|| {}).film.to_rgb();
    let n = image.len() as f32;
    let mean = image.iter().sum::<Rgb>() / n;
    let variance = image.iter().map(|p| (*p - mean) * (*p - mean)).sum::<Rgb>() / (n - 1.0);
    (mean, (variance / n).map(f32::sqrt))
}

/// An orthographic camera looking down −z through a unit-thick box of medium (null walls)
/// at a white sky: every pixel sees exp(−σ_t · 1).
fn slab(medium: &str) -> String {
    format!(
        r#"[camera]
position = [0, 0, 5]
look_at = [0, 0, 0]
orthographic_height = 1.0
resolution = [16, 16]

[render]
integrator = "volpath"
max_depth = -1
sampler = "independent"

[environment]
background = [1, 1, 1]

[materials.boundary]
type = "null"

{medium}

[[shapes]]
type = "box"
min = [-2, -2, -0.5]
max = [2, 2, 0.5]
material = "boundary"
interior = "fog"
"#
    )
}

/// A camera at the centre of a null sphere of `radius` filled with the medium `fog` (defined
/// by `medium`), under a white sky or in the dark.
fn inside_a_sphere_of(medium: &str, radius: f32, white_sky: bool) -> String {
    let sky = if white_sky { "[environment]\nbackground = [1, 1, 1]\n" } else { "" };
    format!(
        r#"[camera]
position = [0, 0, 0]
look_at = [0, 0, 1]
fov = 90
resolution = [12, 12]
medium = "fog"

[render]
integrator = "volpath"
max_depth = -1
sampler = "independent"

{sky}
[materials.boundary]
type = "null"

{medium}

[[shapes]]
type = "sphere"
radius = {radius}
material = "boundary"
interior = "fog"
"#
    )
}

#[test]
fn beer_lambert_through_a_slab_of_homogeneous_medium() {
    let path = scene(
        "slab",
        &slab("[media.fog]\ntype = \"homogeneous\"\nsigma_a = [0.5, 1.0, 2.0]\nsigma_s = [0.0, 0.0, 0.0]"),
        &[],
    );
    let (mean, error) = render_mean(&path, 64, 1);
    let expected = Rgb::new((-0.5f32).exp(), (-1.0f32).exp(), (-2.0f32).exp());
    for c in 0..3 {
        assert!((mean[c] - expected[c]).abs() < 4.0 * error[c] + 1e-4, "channel {c}: {mean} vs {expected} ± {error}");
    }
}

fn vol(resolution: [i32; 3], values: &[f32], min: [f32; 3], max: [f32; 3]) -> Vec<u8> {
    vol_channels(resolution, 1, values, min, max)
}

fn vol_channels(resolution: [i32; 3], channels: i32, values: &[f32], min: [f32; 3], max: [f32; 3]) -> Vec<u8> {
    let mut bytes = b"VOL\x03".to_vec();
    for n in [1, resolution[0], resolution[1], resolution[2], channels] {
        bytes.extend_from_slice(&n.to_le_bytes());
    }
    for f in min.iter().chain(&max).chain(values) {
        bytes.extend_from_slice(&f.to_le_bytes());
    }
    bytes
}

/// The same slab as an absorbing grid (albedo 0) of two voxels, densities ½ and 1 along x:
/// delta tracking's escapes estimate exp(−∫σ_t).
#[test]
fn beer_lambert_through_a_grid_slab() {
    let grid = vol([2, 1, 1], &[0.5, 1.0], [-2.0, -2.0, -0.5], [2.0, 2.0, 0.5]);
    let medium = "[media.fog]\ntype = \"grid\"\nfile = \"density.vol\"\nscale = 2.0\nalbedo = [0, 0, 0]";
    // The voxel centres lie at x = ±1, so over the view (x ∈ [−½, ½]) the density blends
    // linearly, 0.75 + 0.25 x: the pixels' mean transmittance is the mean of
    // exp(−2 (0.75 + 0.25 x)) over the view.
    let path = scene("grid-slab", &slab(medium), &[("density.vol", grid)]);
    let (mean, error) = render_mean(&path, 256, 2);
    let n = 10_000;
    let expected = (0..n)
        .map(|i| {
            let x = -0.5 + (i as f64 + 0.5) / n as f64;
            (-2.0 * (0.75 + 0.25 * x)).exp()
        })
        .sum::<f64>() as f32
        / n as f32;
    for c in 0..3 {
        assert!((mean[c] - expected).abs() < 4.0 * error[c] + 2e-3, "channel {c}: {mean} vs {expected} ± {error}");
    }
}

/// A grid of one colour per channel over only half the slab's thickness, its box placed by a
/// transform (the unit cube scaled and moved, as Mitsuba's `to_world` places volumes): the
/// medium is empty outside that box, so each channel sees exp(−σ_t,c · ½).
#[test]
fn a_chromatic_grid_fills_its_own_box_only() {
    let medium = r#"[media.fog]
type = "grid"
value = [0.5, 1.0, 2.0]
scale = 2.0
albedo = [0, 0, 0]
transform = [{ translate = [-0.5, -0.5, -0.5] }, { scale = [4, 4, 0.5] }, { translate = [0, 0, 0.25] }]"#;
    let path = scene("chromatic-grid", &slab(medium), &[]);
    let (mean, error) = render_mean(&path, 64, 5);
    let expected = Rgb::new((-0.5f32).exp(), (-1.0f32).exp(), (-2.0f32).exp());
    for c in 0..3 {
        assert!((mean[c] - expected[c]).abs() < 4.0 * error[c] + 2e-3, "channel {c}: {mean} vs {expected} ± {error}");
    }
}

/// A lossless medium (albedo 1) inside a null sphere around the camera, under a white sky:
/// light is only redistributed, so radiance is 1 in every direction (the furnace).
#[test]
fn a_lossless_medium_under_a_uniform_sky_conserves_radiance() {
    for (name, medium) in [
        ("homogeneous", "[media.fog]\ntype = \"homogeneous\"\nsigma_t = [0.3, 0.6, 0.9]\nalbedo = [1, 1, 1]\nphase = { type = \"hg\", g = 0.6 }"),
        ("isotropic", "[media.fog]\ntype = \"homogeneous\"\nsigma_s = [0.5, 0.5, 0.5]"),
        // Densities differing by channel and voxel, an albedo field of ones: delta tracking
        // with one channel drawn per flight, weighed over the three.
        (
            "chromatic-grid",
            "[media.fog]\ntype = \"grid\"\nfile = \"density.vol\"\nscale = 1.5\nalbedo = { file = \"albedo.vol\", min = [-3, -3, -3], max = [3, 3, 3] }\nmin = [-3, -3, -3]\nmax = [3, 3, 3]",
        ),
    ] {
        let text = inside_a_sphere_of(medium, 3.0, true);
        let density: Vec<f32> = (0..27).flat_map(|i| [(i % 4) as f32 * 0.3, (i % 3) as f32 * 0.5 + 0.1, 1.0 - (i % 5) as f32 * 0.2]).collect();
        let files = [
            ("density.vol", vol_channels([3, 3, 3], 3, &density, [0.0; 3], [1.0; 3])),
            ("albedo.vol", vol([2, 2, 2], &[1.0; 8], [0.0; 3], [1.0; 3])),
        ];
        let path = scene(&format!("furnace-{name}"), &text, &files);
        let (mean, error) = render_mean(&path, 64, 3);
        for c in 0..3 {
            assert!((mean[c] - 1.0).abs() < 4.0 * error[c] + 2e-3, "{name}, channel {c}: {mean} ± {error}");
        }
    }
}

/// A point light seen through fog by a surface: the shadow ray toward it, unnormalised and
/// crossing the fog box's walls, is attenuated by the fog's thickness alone. A diffuse floor
/// (albedo ½) at z = 0 under a light of intensity 16 at z = 4, with 2 units of absorbing fog
/// (σ_a = 0.3) between: radiance ½/π · 16/4² · e^{−0.6} on the light's path, times e^{−0.6}
/// again on the camera's path down through the same fog.
#[test]
fn a_shadow_ray_through_fog_is_attenuated_by_the_fog_alone() {
    let text = r#"[camera]
position = [0, 0, 10]
look_at = [0, 0, 0]
orthographic_height = 0.02
resolution = [4, 4]

[render]
integrator = "volpath"
max_depth = 1
sampler = "independent"

[materials.boundary]
type = "null"

[materials.floor]
type = "diffuse"
reflectance = [0.5, 0.5, 0.5]

[media.fog]
type = "homogeneous"
sigma_a = [0.3, 0.3, 0.3]

[[lights]]
type = "point"
position = [0, 0, 4]
intensity = 16
falloff = "inverse-square"

[[shapes]]
type = "box"
min = [-5, -5, 1]
max = [5, 5, 3]
material = "boundary"
interior = "fog"

[[shapes]]
type = "quad"
vertices = [[-5, -5, 0], [5, -5, 0], [5, 5, 0], [-5, 5, 0]]
material = "floor"
"#;
    let path = scene("shadow", text, &[]);
    let (mean, error) = render_mean(&path, 1024, 4);
    let expected = 0.5 / std::f32::consts::PI * (16.0 / 16.0) * (-0.6f32).exp() * (-0.6f32).exp();
    for c in 0..3 {
        assert!(
            (mean[c] - expected).abs() < 4.0 * error[c] + 1e-3 * expected,
            "channel {c}: {mean} vs {expected} ± {error}"
        );
    }
}

/// A camera at the centre of a null sphere of emitting medium, in the dark. Absorbing only
/// (σ_a, L_e): every ray sees L_e (1 − e^(−σ_a R)) exactly. Scattering too, in a sphere many
/// mean free paths across: the medium is in equilibrium with its own light, L = L_e (the
/// emission σ_a L_e balances the absorption σ_a L), for a homogeneous medium and a grid alike.
#[test]
fn an_emitting_medium_glows_as_the_transfer_equation_says() {
    let sphere = |name: &str, medium: &str, radius: f32| scene(name, &inside_a_sphere_of(medium, radius, false), &[]);
    let absorbing = sphere(
        "glow-absorbing",
        "[media.fog]\ntype = \"homogeneous\"\nsigma_a = [0.2, 0.5, 1.0]\nemission = [1, 2, 3]",
        2.0,
    );
    let (mean, error) = render_mean(&absorbing, 64, 7);
    let expected = Rgb::new(1.0 - (-0.4f32).exp(), 2.0 * (1.0 - (-1.0f32).exp()), 3.0 * (1.0 - (-2.0f32).exp()));
    for c in 0..3 {
        assert!(
            (mean[c] - expected[c]).abs() < 4.0 * error[c] + 2e-3,
            "absorbing, channel {c}: {mean} vs {expected} ± {error}"
        );
    }
    for (name, medium) in [
        ("glow-homogeneous", "[media.fog]\ntype = \"homogeneous\"\nsigma_t = [1, 1, 1]\nalbedo = [0.7, 0.5, 0.3]\nemission = [1, 2, 3]"),
        ("glow-grid", "[media.fog]\ntype = \"grid\"\nvalue = [1, 1.5, 2]\nmin = [-30, -30, -30]\nmax = [30, 30, 30]\nalbedo = [0.7, 0.5, 0.3]\nemission = [1, 2, 3]"),
    ] {
        let path = sphere(name, medium, 25.0);
        let (mean, error) = render_mean(&path, 32, 8);
        let expected = Rgb::new(1.0, 2.0, 3.0);
        for c in 0..3 {
            assert!(
                (mean[c] - expected[c]).abs() < 4.0 * error[c] + 3e-3 * expected[c],
                "{name}, channel {c}: {mean} vs {expected} ± {error}"
            );
        }
    }
}

/// A box of chromatic fog (null walls) over a diffuse floor, lit by a small area light above:
/// light reaches the camera after any number of scatterings in the fog and bounces off the
/// floor.
const FOG_BOX: &str = r#"[camera]
position = [0, 0.5, 4.5]
look_at = [0, -0.2, 0]
fov = 45
resolution = [32, 32]

[render]
integrator = "volpath"
max_depth = -1
sampler = "independent"

[media.fog]
type = "homogeneous"
sigma_t = [1.5, 2.0, 2.5]
albedo = [0.9, 0.8, 0.7]

[materials.boundary]
type = "null"

[materials.floor]
type = "diffuse"
reflectance = [0.6, 0.6, 0.6]

[materials.lamp]
type = "diffuse"
reflectance = [0, 0, 0]
emission = [8, 8, 8]

[[shapes]]
type = "box"
min = [-1, -1, -1]
max = [1, 1, 1]
material = "boundary"
interior = "fog"

[[shapes]]
type = "quad"
vertices = [[-3, -1.001, -3], [-3, -1.001, 3], [3, -1.001, 3], [3, -1.001, -3]]
material = "floor"

[[shapes]]
type = "quad"
vertices = [[-0.5, 2, -0.5], [0.5, 2, -0.5], [0.5, 2, 0.5], [-0.5, 2, 0.5]]
material = "lamp"
"#;

/// Volumetric photon mapping agrees with the volumetric path tracer on the fog box: the
/// image means within 2 %, and every 8 × 8 block within 10 % (the density estimate's sphere
/// reaches out of the fog near the box's edges and corners, where it reads low). Its kernel's
/// bias shrinks as the map grows (the estimate is consistent): 25,000 photons miss by more
/// than 400,000 do.
#[test]
fn volumetric_photon_mapping_agrees_with_the_volumetric_path_tracer() {
    let path = scene("fog-box", FOG_BOX, &[]);
    let loaded = load_scene(&path).unwrap_or_else(|e| panic!("{e}"));
    let image = |kind: IntegratorKind, photons: u32, spp: u32| {
        let mut integrator_settings = loaded.render.integrator_settings;
        integrator_settings.photon.global_photons = photons;
        let mut renderer = kind.renderer(&integrator_settings, &loaded.scene, 3).unwrap_or_else(|e| panic!("{e}"));
        let settings = RenderSettings { spp, seed: 3, filter: loaded.render.filter, sampler: loaded.render.sampler };
        render_with(&loaded.scene, renderer.as_mut(), &settings, &|| {}).film.to_rgb()
    };
    let reference = image(IntegratorKind::VolPath, 0, 2048);
    let mean = |pixels: &[Rgb]| pixels.iter().sum::<Rgb>() / pixels.len() as f32;
    let block = |pixels: &[Rgb], bx: usize, by: usize| {
        let mut sum = Rgb::ZERO;
        for y in by * 8..by * 8 + 8 {
            for x in bx * 8..bx * 8 + 8 {
                sum += pixels[y * 32 + x];
            }
        }
        sum / 64.0
    };
    let photons = image(IntegratorKind::VolPhoton, 400_000, 128);
    let (a, b) = (mean(&photons), mean(&reference));
    assert!(((a - b) / b).abs().max_element() < 0.02, "means: photons {a}, path tracer {b}");
    for by in 0..4 {
        for bx in 0..4 {
            let (a, b) = (block(&photons, bx, by), block(&reference, bx, by));
            assert!(((a - b) / b).abs().max_element() < 0.1, "block ({bx}, {by}): photons {a}, path tracer {b}");
        }
    }
    let coarse = mean(&image(IntegratorKind::VolPhoton, 25_000, 128));
    let (coarse_error, fine_error) = (((coarse - b) / b).abs().element_sum(), ((a - b) / b).abs().element_sum());
    assert!(fine_error < coarse_error, "bias with 25,000 photons {coarse_error}, with 400,000 {fine_error}");
}

/// Shadow rays pass a thin sheet of glass (Mitsuba's null transmission) with its
/// transmittance 1 − R', R' = 2R / (1 + R) for Fresnel's R: a diffuse floor (albedo ½) under a
/// point light of intensity 16 at height 4, a pane (n = 1.5) at height 2 between them, seen
/// straight down through the same pane. Blocked shadow rays would leave the floor black (a
/// point light cannot be found by sampling).
#[test]
fn a_shadow_ray_through_a_thin_sheet_carries_its_transmittance() {
    let text = r#"[camera]
position = [0, 0, 10]
look_at = [0, 0, 0]
orthographic_height = 2.0
resolution = [16, 16]

[render]
integrator = "volpath"
max_depth = 1
sampler = "independent"

[materials.pane]
type = "thin-dielectric"
int_ior = 1.5
ext_ior = 1.0

[materials.floor]
type = "diffuse"
reflectance = [0.5, 0.5, 0.5]

[[lights]]
type = "point"
position = [0, 0, 4]
intensity = 16
falloff = "inverse-square"

[[shapes]]
type = "quad"
vertices = [[-5, -5, 2], [5, -5, 2], [5, 5, 2], [-5, 5, 2]]
material = "pane"

[[shapes]]
type = "quad"
vertices = [[-5, -5, 0], [5, -5, 0], [5, 5, 0], [-5, 5, 0]]
material = "floor"
"#;
    let path = scene("thin-sheet", text, &[]);
    let (mean, error) = render_mean(&path, 256, 6);
    // Fresnel's reflectance of unpolarised light from air into n = 1.5.
    let fresnel = |cos_i: f64| {
        let sin_t = (1.0 - cos_i * cos_i).sqrt() / 1.5;
        let cos_t = (1.0 - sin_t * sin_t).sqrt();
        let s = (cos_i - 1.5 * cos_t) / (cos_i + 1.5 * cos_t);
        let p = (1.5 * cos_i - cos_t) / (1.5 * cos_i + cos_t);
        0.5 * (s * s + p * p)
    };
    let sheet = |cos: f64| 1.0 - 2.0 * fresnel(cos) / (1.0 + fresnel(cos));
    // The floor's radiance over the view (x, y ∈ [−1, 1]), by the midpoint rule.
    let n = 400;
    let mut sum = 0.0;
    for i in 0..n {
        for j in 0..n {
            let (x, y) = (-1.0 + (i as f64 + 0.5) * 2.0 / n as f64, -1.0 + (j as f64 + 0.5) * 2.0 / n as f64);
            let r2 = x * x + y * y + 16.0;
            let cos = 4.0 / r2.sqrt();
            sum += 0.5 / std::f64::consts::PI * 16.0 * cos / r2 * sheet(cos) * sheet(1.0);
        }
    }
    let expected = (sum / (n * n) as f64) as f32;
    for c in 0..3 {
        assert!(
            (mean[c] - expected).abs() < 4.0 * error[c] + 2e-3 * expected,
            "channel {c}: {mean} vs {expected} ± {error}"
        );
    }
}

/// The medium at a point, as particles leaving lights find it: the side of the first
/// media-bounding surface along a ray, or along the opposite ray when the first meets none.
#[test]
fn the_medium_at_a_point_is_found_from_the_surfaces_around_it() {
    let path = scene("medium-at", &slab("[media.fog]\ntype = \"homogeneous\"\nsigma_a = [1, 1, 1]"), &[]);
    let loaded = load_scene(&path).unwrap_or_else(|e| panic!("{e}"));
    let at = |p: [f32; 3], d: [f32; 3]| loaded.scene.medium_at(p.into(), glint_core::Vec3::from(d).normalize());
    assert_eq!(at([0.0, 0.0, 0.0], [0.0, 0.0, 1.0]), Some(0));
    assert_eq!(at([1.0, -1.0, 0.2], [0.3, 0.1, -1.0]), Some(0));
    // Outside the box, looking away from it (the opposite ray finds its outside) and at it.
    assert_eq!(at([0.0, 0.0, 3.0], [0.0, 0.0, 1.0]), None);
    assert_eq!(at([0.0, 0.0, 3.0], [0.0, 0.0, -1.0]), None);
}

#[test]
fn media_errors_name_what_is_wrong() {
    let bad = |name: &str, medium: &str, expected: &str| {
        let path = scene(name, &slab(medium), &[]);
        let e = load_scene(&path).err().unwrap_or_else(|| panic!("{name}: expected an error")).to_string();
        assert!(e.contains(expected), "{name}: {e}");
    };
    bad("both", "[media.fog]\ntype = \"homogeneous\"\nsigma_a = [1, 1, 1]\nsigma_t = [1, 1, 1]", "not both");
    bad("albedo", "[media.fog]\ntype = \"homogeneous\"\nsigma_t = [1, 1, 1]\nalbedo = [2, 0, 0]", "fraction in [0, 1]");
    bad("g", "[media.fog]\ntype = \"homogeneous\"\nphase = { type = \"hg\", g = 1.5 }", "(−1, 1)");
    bad("unknown", "[media.fgo]\ntype = \"homogeneous\"", "unknown medium `fog`; did you mean `fgo`?");
    bad("file", "[media.fog]\ntype = \"grid\"\nfile = \"missing.vol\"", "missing.vol");
    bad("no data", "[media.fog]\ntype = \"grid\"\nscale = 2", "needs a `file`");
    bad(
        "two boxes",
        "[media.fog]\ntype = \"grid\"\nvalue = [1, 1, 1]\nmin = [0, 0, 0]\nmax = [1, 1, 1]\ntransform = [{ scale = 2 }]",
        "not both",
    );
    bad("flat", "[media.fog]\ntype = \"grid\"\nvalue = [1, 1, 1]\ntransform = [{ scale = [1, 0, 1] }]", "singular");
}

/// Mitsuba's homogeneous medium with an albedo volume that repeats (`wrap_mode` `repeat`,
/// its documentation's textured subsurface bunny): σ_t constant everywhere, the albedo read
/// at each point from the volume repeated past its unit box. Two voxels along x, albedo 0.2
/// and 0.8: x = 0.25 + k reads 0.2 and x = 0.75 + k reads 0.8 for any whole k.
#[test]
fn a_homogeneous_medium_with_a_repeating_albedo_volume() {
    let albedo = vol([2, 1, 1], &[0.2, 0.8], [0.0; 3], [1.0; 3]);
    let xml = r#"<scene version="3.0.0">
    <sensor type="perspective"><film type="hdrfilm"><integer name="width" value="4"/><integer name="height" value="4"/></film></sensor>
    <medium id="m" type="homogeneous">
        <float name="scale" value="2"/>
        <rgb name="sigma_t" value="3"/>
        <volume name="albedo" type="gridvolume">
            <string name="wrap_mode" value="repeat"/>
            <string name="filename" value="albedo.vol"/>
        </volume>
    </medium>
    <shape type="sphere"><float name="radius" value="100"/><ref id="m" name="interior"/><bsdf type="null"/></shape>
</scene>
"#;
    let path = scene("repeat-albedo", xml, &[("albedo.vol", albedo)]);
    let path = path.with_file_name("scene.xml");
    std::fs::write(&path, xml).unwrap();
    let loaded = load_scene(&path).unwrap_or_else(|e| panic!("{e}"));
    let MediumKind::Grid(grid) = &loaded.scene.media()[0].kind else { panic!("a grid medium") };
    for k in [-7.0f32, 0.0, 3.0, 40.0] {
        let p = |x: f32| glint_core::Vec3::new(x + k, 0.5 + 2.0 * k, 0.5 - k);
        assert!((grid.albedo_at(p(0.25)).x - 0.2).abs() < 1e-6, "{k}");
        assert!((grid.albedo_at(p(0.75)).x - 0.8).abs() < 1e-6, "{k}");
        // σ_t = scale × 3 wherever the scene is.
        assert_eq!(grid.sigma_t(p(0.3)), Rgb::splat(6.0));
    }
}

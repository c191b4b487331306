//! The native format's BSDF set: every type builds onto its member, the wrappers resolve their
//! names in any order, and bad references, cycles and over-deep mixtures are clear errors.

use glint_core::materials::Material;
use glint_core::textures::Texture;
use glint_core::Rgb;
use glint_scene::native::Format;
use glint_scene::{parse_scene, LoadedScene, SceneError, Source};

const HEAD: &str = r#"[camera]
position = [0, 0, -5]
look_at = [0, 0, 0]
resolution = [16, 16]

[[shapes]]
type = "sphere"
radius = 1
material = "a"
"#;

fn parse(materials: &str) -> Result<LoadedScene, SceneError> {
    let text = format!("{HEAD}\n{materials}");
    parse_scene(&text, Format::Toml, "bsdfs.toml", &Source::directory(std::env::temp_dir()))
}

fn material<'a>(loaded: &'a LoadedScene, name: &str) -> &'a Material {
    let i = loaded.scene.material_names().iter().position(|n| n == name).unwrap_or_else(|| panic!("{name}"));
    &loaded.scene.materials()[i]
}

#[test]
fn every_type_builds_onto_its_member() {
    let loaded = parse(
        r#"
[materials.a]
type = "blend"
weight = 0.25
first = "metal"
second = "coat"

[materials.metal]
type = "rough-conductor"
metal = "Au"
alpha_u = 0.1
alpha_v = 0.4

[materials.coat]
type = "rough-plastic"
diffuse_reflectance = [0.2, 0.3, 0.4]
alpha = 0.2
two_sided = false

[materials.glass]
type = "dielectric"
int_ior = 1.5

[materials.frost]
type = "rough-dielectric"
distribution = "beckmann"

[materials.pane]
type = "thin-dielectric"

[materials.shiny]
type = "plastic"

[materials.mirror]
type = "conductor"

[materials.leaf]
type = "mask"
opacity = 0.4
material = "paper"

[materials.paper]
type = "diffuse"
reflectance = [0.9, 0.9, 0.9]
emission = [1, 1, 1]

[materials.card]
type = "two-sided"
front = "paper"
back = "mirror"

[materials.lamp]
type = "emitter"
radiance = [5, 5, 5]
material = "shiny"
"#,
    )
    .unwrap_or_else(|e| panic!("{e}"));
    match material(&loaded, "a") {
        Material::Blend(b) => {
            assert_eq!(b.weight, Texture::Constant(Rgb::splat(0.25)));
            match (&b.first, &b.second) {
                (Material::TwoSided(metal), Material::RoughPlastic(coat)) => {
                    assert!(
                        matches!(&metal.front, Material::RoughConductor(m) if (&m.alpha_u, &m.alpha_v) == (&0.1.into(), &0.4.into()))
                    );
                    assert_eq!(coat.alpha, 0.2);
                }
                other => panic!("{other:?}"),
            }
        }
        other => panic!("{other:?}"),
    }
    assert!(matches!(material(&loaded, "glass"), Material::Dielectric(g) if g.eta == 1.5 / 1.000277));
    assert!(matches!(material(&loaded, "frost"), Material::RoughDielectric(f)
        if f.alpha_u == 0.1.into() && f.distribution == glint_core::materials::Distribution::Beckmann));
    assert!(matches!(material(&loaded, "pane"), Material::ThinDielectric(_)));
    assert!(matches!(material(&loaded, "leaf"), Material::Mask(m) if matches!(m.material, Material::Emitter(_))));
    assert!(matches!(material(&loaded, "paper"), Material::Emitter(e) if e.radiance == Texture::Constant(Rgb::ONE)));
    assert!(matches!(material(&loaded, "lamp"), Material::Emitter(e) if matches!(e.surface, Material::TwoSided(_))));
    assert!(matches!(material(&loaded, "card"), Material::TwoSided(t) if t.front != t.back));
}

#[test]
fn references_cycles_and_depth_are_errors_at_their_line() {
    let e = parse("[materials.a]\ntype = \"mask\"\nmaterial = \"papr\"\n\n[materials.paper]\ntype = \"diffuse\"\n")
        .err()
        .unwrap()
        .to_string();
    assert!(e.contains("bsdfs.toml:") && e.contains("unknown material `papr`") && e.contains("paper"), "{e}");
    let e = parse(
        "[materials.a]\ntype = \"two-sided\"\nfront = \"b\"\n\n[materials.b]\ntype = \"mask\"\nmaterial = \"a\"\n",
    )
    .err()
    .unwrap()
    .to_string();
    assert!(e.contains("cycle") && e.contains("a → b → a"), "{e}");
    let blend = |name: &str, first: &str, second: &str| {
        format!("[materials.{name}]\ntype = \"blend\"\nfirst = \"{first}\"\nsecond = \"{second}\"\n\n")
    };
    // (Plastic leaves: a blend of two diffuse materials is one diffuse material.)
    let deep = format!(
        "{}{}{}[materials.d]\ntype = \"plastic\"\n",
        blend("a", "b", "c"),
        blend("b", "d", "c"),
        blend("c", "d", "d")
    );
    let e = parse(&deep).err().unwrap().to_string();
    assert!(e.contains("at most 4"), "{e}");
    let e = parse("[materials.a]\ntype = \"rough-conductor\"\nalpha_u = 0.1\n").err().unwrap().to_string();
    assert!(e.contains("`alpha_u` and `alpha_v`"), "{e}");
    let e = parse("[materials.a]\ntype = \"rough-conductor\"\ndistribution = \"phong\"\n").err().unwrap().to_string();
    assert!(e.contains("unknown microfacet distribution `phong`") && e.contains("`beckmann`"), "{e}");
    let e = parse("[materials.a]\ntype = \"blend\"\nweight = 2\nfirst = \"a\"\nsecond = \"a\"\n")
        .err()
        .unwrap()
        .to_string();
    assert!(e.contains("between 0 and 1"), "{e}");
}

/// `principled`: Mitsuba's defaults, numbers and textures for its weights, `specular` turned
/// into η, and `specular` with `eta`, or a weight out of range, refused at the line.
#[test]
fn principled_builds_with_defaults_textures_and_checked_weights() {
    let loaded = parse(
        r#"
[textures.checks]
type = "checker"
even = [0.1, 0.1, 0.1]
odd = [0.9, 0.9, 0.9]

[materials.a]
type = "principled"
base_color = [0.2, 0.8, 0.1]
metallic = "checks"
clearcoat = 0.6
specular = 0.5

[materials.glass]
type = "principled"
spec_trans = 1
eta = 1
"#,
    )
    .unwrap_or_else(|e| panic!("{e}"));
    match material(&loaded, "a") {
        Material::Principled(p) => {
            assert_eq!(p.base_color, Texture::Constant(Rgb::new(0.2, 0.8, 0.1)));
            assert_eq!(p.roughness, Texture::Constant(Rgb::splat(0.5)));
            assert_eq!(p.sheen, Texture::Constant(Rgb::ZERO));
            assert_eq!(p.clearcoat, Texture::Constant(Rgb::splat(0.6)));
            assert!(matches!(p.metallic, Texture::Checker(_)), "{:?}", p.metallic);
            assert!((p.eta - 1.5).abs() < 1e-6, "{}", p.eta);
        }
        other => panic!("{other:?}"),
    }
    // Mitsuba's adjustment: an index of 1 cannot transmit.
    assert!(matches!(material(&loaded, "glass"), Material::Principled(p) if p.eta == 1.001));
    let e = parse("[materials.a]\ntype = \"principled\"\nspecular = 0.5\neta = 1.4\n").err().unwrap().to_string();
    assert!(e.contains("bsdfs.toml:") && e.contains("`specular` or `eta`"), "{e}");
    let e = parse("[materials.a]\ntype = \"principled\"\nsheen = 1.5\n").err().unwrap().to_string();
    assert!(e.contains("`sheen` must be between 0 and 1"), "{e}");
}

/// Emission given as a texture, on `diffuse` and on `emitter`; an unknown texture is refused
/// at its line.
#[test]
fn emission_may_be_a_texture() {
    let loaded = parse(
        r#"
[textures.checks]
type = "checker"
even = [1, 1, 1]
odd = [4, 4, 4]

[materials.a]
type = "diffuse"
emission = "checks"

[materials.sign]
type = "emitter"
radiance = "checks"
material = "a"
"#,
    )
    .unwrap_or_else(|e| panic!("{e}"));
    for name in ["a", "sign"] {
        match material(&loaded, name) {
            Material::Emitter(e) => assert!(matches!(e.radiance, Texture::Checker(_)), "{name}: {:?}", e.radiance),
            other => panic!("{name}: {other:?}"),
        }
    }
    assert!(loaded.scene.lights().area_count() > 0, "a textured emitter is an area light");
    let e = parse("[materials.a]\ntype = \"diffuse\"\nemission = \"nowhere\"\n").err().unwrap().to_string();
    assert!(e.contains("bsdfs.toml:") && e.contains("unknown texture `nowhere`"), "{e}");
}

/// `principled-thin`: Mitsuba's defaults, `diff_trans` up to 2, a textured `eta`, sampling
/// rates; out-of-range values refused at the line.
#[test]
fn principled_thin_builds_with_defaults_and_checked_ranges() {
    let loaded = parse(
        r#"
[textures.checks]
type = "checker"
even = [1.3, 1.3, 1.3]
odd = [1.6, 1.6, 1.6]

[materials.a]
type = "principled-thin"
base_color = [0.2, 0.6, 0.1]
diff_trans = 1.6
eta = "checks"
specular_transmittance_sampling_rate = 3
"#,
    )
    .unwrap_or_else(|e| panic!("{e}"));
    match material(&loaded, "a") {
        Material::PrincipledThin(p) => {
            assert_eq!(p.base_color, Texture::Constant(Rgb::new(0.2, 0.6, 0.1)));
            assert_eq!((&p.roughness, &p.spec_trans), (&Texture::from(0.5), &Texture::from(0.0)));
            assert_eq!(p.diff_trans, Texture::from(1.6));
            assert!(matches!(p.eta, Texture::Checker(_)), "{:?}", p.eta);
            assert_eq!((p.rates.specular_transmission, p.rates.diffuse_reflection), (3.0, 1.0));
        }
        other => panic!("{other:?}"),
    }
    for (line, message) in [
        ("diff_trans = 2.5", "`diff_trans` must be between 0 and 2"),
        ("sheen = 1.5", "`sheen` must be between 0 and 1"),
        ("eta = 0", "`eta` must be between"),
        ("diffuse_reflectance_sampling_rate = -1", "sampling rate ≥ 0"),
    ] {
        let e = parse(&format!("[materials.a]\ntype = \"principled-thin\"\n{line}\n")).err().unwrap().to_string();
        assert!(e.contains("bsdfs.toml:") && e.contains(message), "{line}: {e}");
    }
}

/// `normal-map` names its texture and material; an unknown texture is an error at its line.
#[test]
fn normal_map_wraps_a_material_about_a_texture() {
    let loaded = parse(
        r#"
[textures.tilt]
type = "checker"
even = [0.5, 0.5, 1.0]
odd = [0.6, 0.5, 0.9]

[materials.a]
type = "normal-map"
normals = "tilt"
material = "paper"

[materials.paper]
type = "diffuse"
"#,
    )
    .unwrap_or_else(|e| panic!("{e}"));
    assert!(matches!(material(&loaded, "a"), Material::NormalMap(m)
        if matches!(m.material, Material::TwoSided(_)) && matches!(m.normals, Texture::Checker(_))));
    let e = parse("[materials.a]\ntype = \"normal-map\"\nnormals = \"nope\"\nmaterial = \"a\"\n")
        .err()
        .unwrap()
        .to_string();
    assert!(e.contains("bsdfs.toml:") && e.contains("nope"), "{e}");
}

#[test]
fn bump_map_wraps_a_material_and_refuses_solid_heights() {
    let loaded = parse(
        r#"
[textures.tiles]
type = "checker"
even = [0.2, 0.2, 0.2]
odd = [0.8, 0.8, 0.8]

[materials.a]
type = "bump-map"
height = "tiles"
scale = 0.05
material = "paper"

[materials.paper]
type = "diffuse"
"#,
    )
    .unwrap_or_else(|e| panic!("{e}"));
    assert!(matches!(material(&loaded, "a"), Material::BumpMap(m)
        if matches!(m.material, Material::TwoSided(_)) && m.scale == 0.05 && matches!(m.height, Texture::Checker(_))));
    let e = parse(
        "[textures.m]\ntype = \"solid-checker\"\neven = [0, 0, 0]\nodd = [1, 1, 1]\n[materials.a]\ntype = \"bump-map\"\nheight = \"m\"\nmaterial = \"b\"\n[materials.b]\ntype = \"diffuse\"\n",
    )
    .err()
    .unwrap()
    .to_string();
    assert!(e.contains("bsdfs.toml:") && e.contains("height") && e.contains("uv"), "{e}");
}

/// A blend of two diffuse materials is one diffuse material whose colour is the two mixed by
/// the weight (the same BSDF and sampling density, and what the path tracer's lanes shade); a
/// blend with anything else stays a blend.
#[test]
fn a_blend_of_two_diffuse_materials_is_diffuse() {
    let loaded = parse(
        r#"
[materials.a]
type = "blend"
weight = 0.25
first = "teal"
second = "yellow"

[materials.teal]
type = "diffuse"
reflectance = [0, 0.5, 0.5]

[materials.yellow]
type = "diffuse"
reflectance = [1, 1, 0]

[materials.b]
type = "blend"
first = "teal"
second = "shiny"

[materials.shiny]
type = "plastic"
"#,
    )
    .unwrap_or_else(|e| panic!("{e}"));
    // The native `diffuse` reflects on both sides: so does the mix.
    let Material::TwoSided(sides) = material(&loaded, "a") else { panic!("{:?}", material(&loaded, "a")) };
    assert_eq!(sides.front, sides.back);
    let Material::Diffuse(mixed) = &sides.front else { panic!("{:?}", sides.front) };
    let Texture::Mix(_) = &mixed.reflectance else { panic!("{:?}", mixed.reflectance) };
    let colour = mixed.reflectance.evaluate(&Default::default());
    assert!((colour - Rgb::new(0.25, 0.625, 0.375)).abs().max_element() < 1e-6, "{colour:?}");
    assert!(matches!(material(&loaded, "b"), Material::Blend(_)));
}

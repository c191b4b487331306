//! The native scene format as serde types: exactly the fields docs/scene-format.md lists.
//! Every struct denies unknown fields, so a typo is an error, never silently ignored.

use std::collections::BTreeMap;

use glint_core::integrators::PhotonSettings;
use glint_core::lights::{LightSelection, TriangleSampling};
use glint_core::sampling::SamplerKind;
use glint_core::Named;
use serde::Deserialize;

use crate::located::Located;

pub type Vector = [f32; 3];

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
pub struct SceneFile {
    pub camera: Located<CameraDesc>,
    #[serde(default)]
    pub render: RenderDesc,
    #[serde(default)]
    pub intersection: IntersectionDesc,
    #[serde(default)]
    pub environment: EnvironmentDesc,
    #[serde(default)]
    pub textures: BTreeMap<String, Located<TextureDesc>>,
    #[serde(default)]
    pub materials: BTreeMap<String, Located<MaterialDesc>>,
    #[serde(default)]
    pub meshes: BTreeMap<String, Located<MeshDesc>>,
    #[serde(default)]
    pub lights: Vec<Located<LightDesc>>,
    #[serde(default)]
    pub shapes: Vec<Located<ShapeDesc>>,
    /// Participating media, by name: shapes bound them (`interior`, `exterior`), the camera
    /// may be in one (`medium`).
    #[serde(default)]
    pub media: BTreeMap<String, Located<MediumDesc>>,
}

impl SceneFile {
    /// A scene of nothing but `camera` and `render` (what the other formats' readers fill).
    pub fn new(camera: CameraDesc, render: RenderDesc) -> Self {
        Self {
            camera: Located { value: camera, span: None },
            render,
            intersection: IntersectionDesc::default(),
            environment: EnvironmentDesc::default(),
            textures: BTreeMap::new(),
            materials: BTreeMap::new(),
            meshes: BTreeMap::new(),
            lights: Vec::new(),
            shapes: Vec::new(),
            media: BTreeMap::new(),
        }
    }
}

/// A participating medium.
#[derive(Deserialize, Debug)]
#[serde(tag = "type", rename_all = "kebab-case", deny_unknown_fields)]
pub enum MediumDesc {
    /// σ_a and σ_s, or σ_t and the albedo σ_s / σ_t (per channel, per unit length), each
    /// times `scale`.
    Homogeneous {
        sigma_a: Option<Vector>,
        sigma_s: Option<Vector>,
        sigma_t: Option<Vector>,
        albedo: Option<Vector>,
        scale: Option<f32>,
        phase: Option<PhaseDesc>,
        /// Radiance emitted where the medium absorbs (σ_a × this per unit length).
        emission: Option<Vector>,
    },
    /// σ_t = `scale` × a density field: a Mitsuba `.vol` grid (`file`, one channel or three)
    /// or one `value` (per channel), over a box: the file's own, or `min`–`max`, or the unit
    /// cube moved by `transform` (as Mitsuba's `to_world`). The medium is empty outside the
    /// box. The `albedo` is a constant or a field of its own.
    Grid {
        file: Option<String>,
        value: Option<Vector>,
        min: Option<Vector>,
        max: Option<Vector>,
        #[serde(default)]
        transform: Vec<TransformOp>,
        albedo: Option<AlbedoDesc>,
        scale: Option<f32>,
        phase: Option<PhaseDesc>,
        emission: Option<Vector>,
    },
}

/// A grid medium's albedo: one colour, or a `.vol` field placed as the density's is.
#[derive(Deserialize, Debug)]
#[serde(untagged)]
pub enum AlbedoDesc {
    Constant(Vector),
    Field(AlbedoField),
}

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
pub struct AlbedoField {
    pub file: String,
    pub min: Option<Vector>,
    pub max: Option<Vector>,
    #[serde(default)]
    pub transform: Vec<TransformOp>,
}

#[derive(Deserialize, Debug, Clone, Copy)]
#[serde(tag = "type", rename_all = "kebab-case", deny_unknown_fields)]
pub enum PhaseDesc {
    Isotropic,
    /// Henyey–Greenstein, mean cosine `g` in (−1, 1).
    Hg {
        g: f32,
    },
}

/// A mesh loaded once and placed any number of times by `instance` shapes.
#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
pub struct MeshDesc {
    /// A mesh file, or else `data`.
    pub file: Option<String>,
    pub data: Option<MeshData>,
    /// Which mesh of a file that holds several, as for a `mesh` shape.
    #[serde(default)]
    pub shape_index: u32,
    #[serde(default = "yes")]
    pub smooth: bool,
    /// v ← 1 − v for the file's texture coordinates, as for a `mesh` shape.
    #[serde(default)]
    pub flip_v: bool,
    /// Smooth normals where the file has none, as for a `mesh` shape.
    #[serde(default)]
    pub compute_normals: bool,
}

/// A triangle mesh written in the scene itself (pbrt's `trianglemesh`, glTF's primitives):
/// `normals` and `uvs`, if given, one per position.
#[derive(Deserialize, Debug, Clone, Default)]
#[serde(deny_unknown_fields)]
pub struct MeshData {
    pub positions: Vec<Vector>,
    pub indices: Vec<[u32; 3]>,
    pub normals: Option<Vec<Vector>>,
    pub uvs: Option<Vec<[f32; 2]>>,
}

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
pub struct CameraDesc {
    pub position: Vector,
    pub look_at: Vector,
    #[serde(default = "default_up")]
    pub up: Vector,
    #[serde(default = "default_fov")]
    pub fov: f32,
    #[serde(default = "default_resolution")]
    pub resolution: [u32; 2],
    /// A thin lens: the aperture's radius and the distance in focus (scene units).
    pub aperture_radius: Option<f32>,
    pub focus_distance: Option<f32>,
    /// An orthographic camera: the view's height in scene units.
    pub orthographic_height: Option<f32>,
    /// The image mirrored left to right (its right is up × forward instead of forward × up):
    /// cameras of left-handed formats (pbrt's) and mirroring transforms.
    #[serde(default)]
    pub mirror: bool,
    /// The medium the camera is in (a name in `[media]`).
    pub medium: Option<String>,
}

fn default_up() -> Vector {
    [0.0, 1.0, 0.0]
}
fn default_fov() -> f32 {
    45.0
}
fn default_resolution() -> [u32; 2] {
    [640, 480]
}

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
pub struct RenderDesc {
    #[serde(default = "default_spp")]
    pub spp: u32,
    #[serde(default = "default_max_depth")]
    pub max_depth: i64,
    #[serde(default = "default_rr_depth")]
    pub rr_depth: u32,
    #[serde(default = "default_integrator")]
    pub integrator: String,
    #[serde(default)]
    pub seed: u64,
    #[serde(default = "default_min_contribution")]
    pub min_contribution: f32,
    #[serde(default)]
    pub transparent_shadows: bool,
    #[serde(default = "default_filter")]
    pub filter: String,
    #[serde(default = "default_sampler")]
    pub sampler: String,
    #[serde(default = "default_light_sampling")]
    pub light_sampling: String,
    #[serde(default = "default_light_selection")]
    pub light_selection: String,
    /// Keep each pixel's second moment and write it beside the image (Mitsuba's `moment`).
    #[serde(default)]
    pub moment: bool,
    /// Photon mapping (see `PhotonSettings`).
    #[serde(default = "default_photons")]
    pub photons: u32,
    #[serde(default = "default_photons")]
    pub caustic_photons: u32,
    #[serde(default = "default_photon_nearest")]
    pub photon_nearest: u32,
    #[serde(default)]
    pub photon_radius: f32,
    #[serde(default = "default_final_gather")]
    pub final_gather: u32,
    /// SPPM.
    #[serde(default)]
    pub sppm_radius: f32,
    #[serde(default)]
    pub photons_per_pass: u32,
}

fn default_sampler() -> String {
    SamplerKind::default().name().into()
}
fn default_light_sampling() -> String {
    TriangleSampling::default().name().into()
}
fn default_light_selection() -> String {
    LightSelection::default().name().into()
}
fn default_photons() -> u32 {
    PhotonSettings::default().global_photons
}
fn default_photon_nearest() -> u32 {
    PhotonSettings::default().nearest
}
fn default_final_gather() -> u32 {
    PhotonSettings::default().final_gather
}

impl Default for RenderDesc {
    fn default() -> Self {
        Self {
            spp: default_spp(),
            max_depth: default_max_depth(),
            rr_depth: default_rr_depth(),
            integrator: default_integrator(),
            seed: 0,
            min_contribution: default_min_contribution(),
            transparent_shadows: false,
            filter: default_filter(),
            sampler: default_sampler(),
            light_sampling: default_light_sampling(),
            light_selection: default_light_selection(),
            moment: false,
            photons: default_photons(),
            caustic_photons: default_photons(),
            photon_nearest: default_photon_nearest(),
            photon_radius: 0.0,
            final_gather: default_final_gather(),
            sppm_radius: 0.0,
            photons_per_pass: 0,
        }
    }
}

fn default_filter() -> String {
    "box".into()
}

fn default_min_contribution() -> f32 {
    1e-3
}

fn default_spp() -> u32 {
    1
}
fn default_max_depth() -> i64 {
    5
}
fn default_rr_depth() -> u32 {
    5
}
fn default_integrator() -> String {
    "raycast".into()
}

#[derive(Deserialize, Debug, Default)]
#[serde(deny_unknown_fields)]
pub struct IntersectionDesc {
    /// Names of the core's methods (`Named`), parsed by the builder; `None`: the default.
    pub sphere: Option<String>,
    pub triangle: Option<String>,
    pub polygon: Option<String>,
    #[serde(rename = "box")]
    pub aabox: Option<String>,
}

#[derive(Deserialize, Debug, Default)]
#[serde(deny_unknown_fields)]
pub struct EnvironmentDesc {
    #[serde(default)]
    pub background: Vector,
    #[serde(default)]
    pub ambient: Vector,
    /// An equirectangular environment map (EXR for HDR), relative to the scene.
    pub map: Option<String>,
    pub map_scale: Option<f32>,
    /// Rotations of the map (applied in order).
    #[serde(default)]
    pub map_transform: Vec<TransformOp>,
}

#[derive(Deserialize, Debug)]
#[serde(tag = "type", rename_all = "kebab-case", deny_unknown_fields)]
pub enum MaterialDesc {
    Phong {
        diffuse: Option<ColorDesc>,
        ambient: Option<ColorDesc>,
        specular: Option<ColorDesc>,
        shininess: Option<f32>,
        reflection: Option<ColorDesc>,
        transmission: Option<ColorDesc>,
        ior: Option<f32>,
        #[serde(default)]
        fresnel: FresnelDesc,
        roughness: Option<f32>,
        emission: Option<Vector>,
        #[serde(default)]
        two_sided_emission: bool,
    },
    /// A metal: a mirror (or GGX, with `roughness`) whose reflectance is the conductor
    /// Fresnel of `metal` (a name) or of `eta` and `k`, times `tint`.
    Metal {
        metal: Option<String>,
        eta: Option<Vector>,
        k: Option<Vector>,
        tint: Option<ColorDesc>,
        roughness: Option<f32>,
    },
    /// A Lambertian surface (Mitsuba's `diffuse`), two-sided unless `two_sided = false`.
    Diffuse {
        reflectance: Option<ColorDesc>,
        /// Radiance emitted: a colour or a texture over the surface's uv.
        emission: Option<ColorDesc>,
        #[serde(default)]
        two_sided_emission: bool,
        two_sided: Option<bool>,
    },
    /// No surface at all (Mitsuba's `null`): a medium's boundary that light crosses unchanged.
    Null,
    /// Lambert's lobe on both sides of a sheet (pbrt's `diffusetransmission`).
    DiffuseTransmission { reflectance: Option<ColorDesc>, transmittance: Option<ColorDesc> },
    /// A smooth metal (Mitsuba's `conductor`): `metal` (a name) or `eta` and `k`.
    Conductor {
        metal: Option<String>,
        eta: Option<Vector>,
        k: Option<Vector>,
        specular_reflectance: Option<ColorDesc>,
        two_sided: Option<bool>,
    },
    /// A rough metal (Mitsuba's `roughconductor`): `alpha`, or `alpha_u` and `alpha_v`, each
    /// a number or a texture's name.
    RoughConductor {
        metal: Option<String>,
        eta: Option<Vector>,
        k: Option<Vector>,
        specular_reflectance: Option<ColorDesc>,
        alpha: Option<FractionDesc>,
        alpha_u: Option<FractionDesc>,
        alpha_v: Option<FractionDesc>,
        /// `"ggx"` (default) or `"beckmann"`.
        distribution: Option<String>,
        two_sided: Option<bool>,
    },
    /// Smooth glass (Mitsuba's `dielectric`).
    Dielectric {
        int_ior: Option<f32>,
        ext_ior: Option<f32>,
        specular_reflectance: Option<ColorDesc>,
        specular_transmittance: Option<ColorDesc>,
    },
    /// Rough glass (Mitsuba's `roughdielectric`): widths as numbers or texture names.
    RoughDielectric {
        int_ior: Option<f32>,
        ext_ior: Option<f32>,
        specular_reflectance: Option<ColorDesc>,
        specular_transmittance: Option<ColorDesc>,
        alpha: Option<FractionDesc>,
        alpha_u: Option<FractionDesc>,
        alpha_v: Option<FractionDesc>,
        /// `"ggx"` (default) or `"beckmann"`.
        distribution: Option<String>,
    },
    /// A thin pane (Mitsuba's `thindielectric`).
    ThinDielectric {
        int_ior: Option<f32>,
        ext_ior: Option<f32>,
        specular_reflectance: Option<ColorDesc>,
        specular_transmittance: Option<ColorDesc>,
    },
    /// A diffuse base under a smooth coat (Mitsuba's `plastic`).
    Plastic {
        diffuse_reflectance: Option<ColorDesc>,
        specular_reflectance: Option<ColorDesc>,
        int_ior: Option<f32>,
        ext_ior: Option<f32>,
        #[serde(default)]
        nonlinear: bool,
        two_sided: Option<bool>,
    },
    /// A diffuse base under a rough coat (Mitsuba's `roughplastic`, GGX).
    RoughPlastic {
        diffuse_reflectance: Option<ColorDesc>,
        specular_reflectance: Option<ColorDesc>,
        int_ior: Option<f32>,
        ext_ior: Option<f32>,
        #[serde(default)]
        nonlinear: bool,
        alpha: Option<f32>,
        /// `"ggx"` (default) or `"beckmann"`.
        distribution: Option<String>,
        two_sided: Option<bool>,
    },
    /// Disney's principled BSDF (Mitsuba's `principled`): each weight a number in [0, 1] or a
    /// texture's luminance; `specular` (in [0, 1]) or `eta` sets the index.
    Principled {
        base_color: Option<ColorDesc>,
        roughness: Option<FractionDesc>,
        anisotropic: Option<FractionDesc>,
        metallic: Option<FractionDesc>,
        spec_trans: Option<FractionDesc>,
        specular: Option<f32>,
        eta: Option<f32>,
        spec_tint: Option<FractionDesc>,
        sheen: Option<FractionDesc>,
        sheen_tint: Option<FractionDesc>,
        flatness: Option<FractionDesc>,
        clearcoat: Option<FractionDesc>,
        clearcoat_gloss: Option<FractionDesc>,
    },
    /// Disney's thin-sheet principled BSDF (Mitsuba's `principledthin`): the weights as in
    /// `principled`, `diff_trans` in [0, 2], `eta` a number or texture, and the lobes'
    /// sampling rates.
    PrincipledThin {
        base_color: Option<ColorDesc>,
        roughness: Option<FractionDesc>,
        anisotropic: Option<FractionDesc>,
        spec_trans: Option<FractionDesc>,
        diff_trans: Option<FractionDesc>,
        eta: Option<FractionDesc>,
        spec_tint: Option<FractionDesc>,
        sheen: Option<FractionDesc>,
        sheen_tint: Option<FractionDesc>,
        flatness: Option<FractionDesc>,
        diffuse_reflectance_sampling_rate: Option<f32>,
        specular_reflectance_sampling_rate: Option<f32>,
        specular_transmittance_sampling_rate: Option<f32>,
        diffuse_transmittance_sampling_rate: Option<f32>,
    },
    /// (1 − weight)·first + weight·second (Mitsuba's `blendbsdf`); materials by name.
    Blend { weight: Option<FractionDesc>, first: String, second: String },
    /// `material` where the surface is, passed through elsewhere (Mitsuba's `mask`).
    Mask { opacity: Option<FractionDesc>, material: String },
    /// `material` about the shading normal a texture gives (Mitsuba's `normalmap`).
    NormalMap { normals: ColorDesc, material: String },
    /// `material` about a normal tilted by the height field `height` (a texture of uv, its
    /// luminance) times `scale` (Mitsuba's `bumpmap`).
    BumpMap {
        height: String,
        #[serde(default = "one")]
        scale: f32,
        material: String,
    },
    /// One material per side (Mitsuba's `twosided` with two BSDFs); `back` defaults to `front`.
    TwoSided { front: String, back: Option<String> },
    /// `material` emitting `radiance`, a colour or a texture over the surface's uv (Mitsuba's
    /// `area` emitter on a shape).
    Emitter {
        radiance: ColorDesc,
        #[serde(default)]
        two_sided: bool,
        material: String,
    },
}

/// A fraction in [0, 1]: a number, or the name of a texture (its luminance).
#[derive(Deserialize, Debug, Clone)]
#[serde(untagged)]
pub enum FractionDesc {
    Number(f32),
    Texture(String),
}

/// A colour, or the name of a texture in `[textures]`.
#[derive(Deserialize, Debug, Clone)]
#[serde(untagged)]
pub enum ColorDesc {
    Rgb(Vector),
    Texture(String),
}

#[derive(Deserialize, Debug, Default, Clone, Copy)]
#[serde(rename_all = "kebab-case")]
pub enum FresnelDesc {
    #[default]
    None,
    Schlick,
    Exact,
}

/// A number for both axes or one per axis.
#[derive(Deserialize, Debug, Clone, Copy)]
#[serde(untagged)]
pub enum Scale2Desc {
    Uniform(f32),
    PerAxis([f32; 2]),
}

#[derive(Deserialize, Debug, Clone)]
#[serde(tag = "type", rename_all = "kebab-case", deny_unknown_fields)]
pub enum TextureDesc {
    Checker {
        even: Vector,
        odd: Vector,
        scale: Option<Scale2Desc>,
        /// An affine map of uv after `scale`: rows [a, b, c] and [d, e, f].
        uv_transform: Option<[[f32; 3]; 2]>,
    },
    SolidChecker {
        even: Vector,
        odd: Vector,
        scale: Option<f32>,
    },
    Image {
        file: String,
        #[serde(default)]
        wrap: WrapDesc,
        #[serde(default)]
        filter: TexelFilterDesc,
        scale: Option<Scale2Desc>,
        uv_transform: Option<[[f32; 3]; 2]>,
        /// The stored values as they are (normal maps, data), not decoded from sRGB.
        #[serde(default)]
        raw: bool,
        /// One channel (0 red, 1 green, 2 blue) as grey: packed data, as glTF's
        /// metallic-roughness maps.
        channel: Option<u8>,
        /// A factor for every texel (glTF's colour factors, pbrt's `scale`).
        tint: Option<Vector>,
    },
    Marble {
        base: Vector,
        vein: Vector,
        scale: Option<f32>,
        turbulence: Option<f32>,
        octaves: Option<u32>,
    },
    Wood {
        light: Vector,
        dark: Vector,
        rings: Option<f32>,
        turbulence: Option<f32>,
    },
    /// A mesh's own values (`vertex_color`, `face_weight`, …: Mitsuba's `mesh_attribute`).
    MeshAttribute {
        name: String,
        scale: Option<f32>,
    },
}

#[derive(Deserialize, Debug, Default, Clone, Copy)]
#[serde(rename_all = "kebab-case")]
pub enum WrapDesc {
    #[default]
    Repeat,
    Clamp,
    Mirror,
}

#[derive(Deserialize, Debug, Default, Clone, Copy)]
#[serde(rename_all = "kebab-case")]
pub enum TexelFilterDesc {
    #[default]
    Bilinear,
    Nearest,
}

#[derive(Deserialize, Debug)]
#[serde(tag = "type", rename_all = "kebab-case", deny_unknown_fields)]
pub enum LightDesc {
    Point {
        position: Vector,
        #[serde(default = "white")]
        color: Vector,
        #[serde(default = "one")]
        intensity: f32,
        #[serde(default)]
        falloff: FalloffDesc,
    },
    Spot {
        position: Vector,
        direction: Vector,
        /// Half-angle in degrees (30 unless `focal_length` gives it).
        cone_angle: Option<f32>,
        /// A projector's lens in mm on 35 mm film (36 × 24), the film's diagonal spanning the
        /// slide's: its cone follows (Mitsuba's projector without `fov`: 50).
        focal_length: Option<f32>,
        #[serde(default = "default_edge")]
        edge: f32,
        /// `"smooth"` (default) or `"linear"` (in the angle, as Mitsuba's spot).
        profile: Option<String>,
        /// A texture projected across the cone, and the slide's up direction.
        texture: Option<String>,
        up: Option<Vector>,
        #[serde(default = "white")]
        color: Vector,
        #[serde(default = "one")]
        intensity: f32,
        #[serde(default)]
        falloff: FalloffDesc,
    },
    Directional {
        direction: Vector,
        #[serde(default = "white")]
        color: Vector,
        #[serde(default = "one")]
        intensity: f32,
    },
}

fn default_edge() -> f32 {
    5.0
}
fn white() -> Vector {
    [1.0; 3]
}
fn one() -> f32 {
    1.0
}

#[derive(Deserialize, Debug, Default, Clone, Copy)]
#[serde(rename_all = "kebab-case")]
pub enum FalloffDesc {
    #[default]
    None,
    InverseSquare,
}

/// Shapes. `material` names an entry of `[materials]`; `transform` is a list of operations
/// applied in order (the first one is applied to the shape first); `name` is for messages.
#[derive(Deserialize, Debug, Clone)]
#[serde(tag = "type", rename_all = "kebab-case", deny_unknown_fields)]
pub enum ShapeDesc {
    Sphere {
        #[serde(default)]
        center: Vector,
        radius: f32,
        material: String,
        /// Media inside (behind the normals) and outside (names in `[media]`).
        interior: Option<String>,
        exterior: Option<String>,
        #[serde(default)]
        transform: Vec<TransformOp>,
        name: Option<String>,
    },
    Plane {
        normal: Vector,
        offset: Option<f32>,
        point: Option<Vector>,
        material: String,
        #[serde(default)]
        transform: Vec<TransformOp>,
        name: Option<String>,
    },
    Triangle {
        vertices: [Vector; 3],
        normals: Option<[Vector; 3]>,
        uvs: Option<[[f32; 2]; 3]>,
        material: String,
        #[serde(default)]
        transform: Vec<TransformOp>,
        name: Option<String>,
    },
    Polygon {
        vertices: Vec<Vector>,
        uvs: Option<Vec<[f32; 2]>>,
        material: String,
        #[serde(default)]
        transform: Vec<TransformOp>,
        name: Option<String>,
    },
    Box {
        min: Vector,
        max: Vector,
        material: String,
        /// Media inside (behind the normals) and outside (names in `[media]`).
        interior: Option<String>,
        exterior: Option<String>,
        #[serde(default)]
        transform: Vec<TransformOp>,
        name: Option<String>,
    },
    /// A mesh file, or the mesh itself in `data`.
    Mesh {
        file: Option<String>,
        data: Option<MeshData>,
        /// Which mesh of a file that holds several (a Mitsuba `.serialized` file).
        #[serde(default)]
        shape_index: u32,
        #[serde(default = "yes")]
        smooth: bool,
        /// v ← 1 − v for the file's texture coordinates (files whose v runs down the image).
        #[serde(default)]
        flip_v: bool,
        /// Where the file has no normals (and `smooth`), make smooth ones as Mitsuba does.
        #[serde(default)]
        compute_normals: bool,
        material: String,
        /// Media inside (behind the normals) and outside (names in `[media]`).
        interior: Option<String>,
        exterior: Option<String>,
        #[serde(default)]
        transform: Vec<TransformOp>,
        name: Option<String>,
    },
    /// Four corners v0..v3, split into triangles (v0, v1, v2) and (v0, v2, v3); flat-shaded with
    /// the normal (v1 − v0) × (v2 − v0); uv (0,0), (1,0), (1,1), (0,1) at the corners.
    Quad {
        vertices: [Vector; 4],
        material: String,
        /// Media inside (behind the normals) and outside (names in `[media]`).
        interior: Option<String>,
        exterior: Option<String>,
        #[serde(default)]
        transform: Vec<TransformOp>,
        name: Option<String>,
    },
    Instance {
        mesh: String,
        material: String,
        /// Media inside (behind the normals) and outside (names in `[media]`).
        interior: Option<String>,
        exterior: Option<String>,
        #[serde(default)]
        transform: Vec<TransformOp>,
        name: Option<String>,
    },
    /// The surface where a grid of signed distances over the unit cube changes sign (a
    /// Mitsuba `.vol` file of one channel, its own box ignored: the grid spans [0, 1]³, placed
    /// by `transform`); `normals` `smooth` (default) or `analytic`.
    SdfGrid {
        file: String,
        normals: Option<String>,
        material: String,
        #[serde(default)]
        transform: Vec<TransformOp>,
        name: Option<String>,
    },
    /// Constructive solid geometry: `operation` (`union`, `intersection`, or `difference`: the
    /// first operand less the others) over two or more closed `operands`.
    Csg {
        operation: String,
        operands: Vec<OperandDesc>,
        material: String,
        #[serde(default)]
        transform: Vec<TransformOp>,
        name: Option<String>,
    },
}

/// A CSG operand (not `Located`: serde buffers a tagged enum's fields, and a span cannot be
/// read back from the buffer; errors name the operand's path instead): a closed solid (planes, polygons, triangles and open meshes bound none), its
/// material its own or, if not given, the enclosing node's.
#[derive(Deserialize, Debug, Clone)]
#[serde(tag = "type", rename_all = "kebab-case", deny_unknown_fields)]
pub enum OperandDesc {
    Sphere {
        #[serde(default)]
        center: Vector,
        radius: f32,
        material: Option<String>,
        #[serde(default)]
        transform: Vec<TransformOp>,
    },
    Box {
        min: Vector,
        max: Vector,
        material: Option<String>,
        #[serde(default)]
        transform: Vec<TransformOp>,
    },
    /// A closed mesh of `[meshes]`, through its own BVH.
    Instance {
        mesh: String,
        material: Option<String>,
        #[serde(default)]
        transform: Vec<TransformOp>,
    },
    Csg {
        operation: String,
        operands: Vec<OperandDesc>,
        material: Option<String>,
        #[serde(default)]
        transform: Vec<TransformOp>,
    },
}

fn yes() -> bool {
    true
}

impl ShapeDesc {
    pub fn common(&self) -> (&str, &[TransformOp], Option<&str>) {
        match self {
            ShapeDesc::Sphere { material, transform, name, .. }
            | ShapeDesc::Plane { material, transform, name, .. }
            | ShapeDesc::Triangle { material, transform, name, .. }
            | ShapeDesc::Polygon { material, transform, name, .. }
            | ShapeDesc::Box { material, transform, name, .. }
            | ShapeDesc::Mesh { material, transform, name, .. }
            | ShapeDesc::Quad { material, transform, name, .. }
            | ShapeDesc::Instance { material, transform, name, .. }
            | ShapeDesc::Csg { material, transform, name, .. }
            | ShapeDesc::SdfGrid { material, transform, name, .. } => (material, transform, name.as_deref()),
        }
    }

    /// The shape's transform and name, to place a copy of it elsewhere.
    pub fn placement_mut(&mut self) -> (&mut Vec<TransformOp>, &mut Option<String>) {
        match self {
            ShapeDesc::Sphere { transform, name, .. }
            | ShapeDesc::Plane { transform, name, .. }
            | ShapeDesc::Triangle { transform, name, .. }
            | ShapeDesc::Polygon { transform, name, .. }
            | ShapeDesc::Box { transform, name, .. }
            | ShapeDesc::Mesh { transform, name, .. }
            | ShapeDesc::Quad { transform, name, .. }
            | ShapeDesc::Instance { transform, name, .. }
            | ShapeDesc::Csg { transform, name, .. }
            | ShapeDesc::SdfGrid { transform, name, .. } => (transform, name),
        }
    }

    /// A mesh shape as an instance named `mesh`, with the mesh it places (for `[meshes]`), so
    /// that every placement shares one BVH (Mitsuba's shapegroups, pbrt's objects); any other
    /// shape as it is, with no mesh.
    pub fn into_instance(self, mesh: &str) -> (ShapeDesc, Option<MeshDesc>) {
        match self {
            ShapeDesc::Mesh {
                file,
                data,
                shape_index,
                smooth,
                flip_v,
                compute_normals,
                material,
                transform,
                name,
                interior,
                exterior,
            } => (
                ShapeDesc::Instance { interior, exterior, mesh: mesh.to_string(), material, transform, name },
                Some(MeshDesc { file, data, shape_index, smooth, flip_v, compute_normals }),
            ),
            other => (other, None),
        }
    }

    /// The media inside and outside the shape, where it bounds any.
    pub fn media(&self) -> (Option<&str>, Option<&str>) {
        match self {
            ShapeDesc::Sphere { interior, exterior, .. }
            | ShapeDesc::Box { interior, exterior, .. }
            | ShapeDesc::Mesh { interior, exterior, .. }
            | ShapeDesc::Quad { interior, exterior, .. }
            | ShapeDesc::Instance { interior, exterior, .. } => (interior.as_deref(), exterior.as_deref()),
            _ => (None, None),
        }
    }

    pub fn kind(&self) -> &'static str {
        match self {
            ShapeDesc::Sphere { .. } => "sphere",
            ShapeDesc::Plane { .. } => "plane",
            ShapeDesc::Triangle { .. } => "triangle",
            ShapeDesc::Polygon { .. } => "polygon",
            ShapeDesc::Box { .. } => "box",
            ShapeDesc::Mesh { .. } => "mesh",
            ShapeDesc::Quad { .. } => "quad",
            ShapeDesc::Instance { .. } => "instance",
            ShapeDesc::Csg { .. } => "csg",
            ShapeDesc::SdfGrid { .. } => "sdf-grid",
        }
    }
}

#[derive(Deserialize, Debug, Clone)]
#[serde(rename_all = "kebab-case", deny_unknown_fields)]
pub enum TransformOp {
    Translate(Vector),
    Rotate(RotateDesc),
    Scale(ScaleDesc),
    /// Row-major 4×4 matrix (the last row is normally [0, 0, 0, 1]).
    Matrix([[f32; 4]; 4]),
}

#[derive(Deserialize, Debug, Clone)]
#[serde(deny_unknown_fields)]
pub struct RotateDesc {
    pub axis: Vector,
    /// Degrees, counter-clockwise looking down the axis toward the origin (right-hand rule).
    pub angle: f32,
}

#[derive(Deserialize, Debug, Clone, Copy)]
#[serde(untagged)]
pub enum ScaleDesc {
    Uniform(f32),
    PerAxis(Vector),
}

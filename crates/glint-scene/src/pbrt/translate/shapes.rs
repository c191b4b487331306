//! Shapes: pbrt's sphere, disk, cylinder, triangle and bilinear meshes, Loop subdivision
//! surfaces, PLY meshes and curves, each made in its own space (quadrics and patches as
//! meshes, by `pbrt/shapes.rs`), placed by the current transform, given the current material
//! (an emitter under an area light) and wound as pbrt faces it.

use glam::{Mat4, Vec2, Vec3, Vec4};

use super::state::matrix_op;
use super::{Result, Translator};
use crate::located::Located;
use crate::native::schema::*;
use crate::pbrt::params::{Failure, Params};
use crate::pbrt::parse::{At, Directive};
use crate::pbrt::shapes;

impl Translator<'_> {
    pub(super) fn shape(&mut self, d: &Directive) -> Result<()> {
        let p = self.params(d);
        let kind = d.args[0].as_str();
        // pbrt's alpha: the surface is there with that probability (0: a hole, 1: solid), for
        // every ray, shadow rays too: glint's mask.
        let alpha = match self.fraction(&p, "alpha")? {
            Some(FractionDesc::Number(a)) if a >= 1.0 => None,
            Some(FractionDesc::Number(a)) if a.is_nan() => {
                return Err(self.parser.error(self.param_at(&p, "alpha"), "`alpha` must be a number, got NaN"))
            }
            Some(FractionDesc::Number(a)) => Some(FractionDesc::Number(a.max(0.0))),
            other => other,
        };
        p.ignore(&["emissionfilename"]);
        let f = |r: std::result::Result<f32, Failure>| r.map_err(|x| self.fail(x));
        let (ctm, reverse) = (self.state.ctm, self.state.reverse_orientation);
        if kind == "curve" {
            return self.curve(d, &p, alpha);
        }
        // Shapes are made in their own space and placed by the current transform.
        let mut data = match kind {
            "sphere" => {
                let radius = f(p.float("radius", 1.0))?;
                let (z0, z1) = (f(p.float("zmin", -radius))?, f(p.float("zmax", radius))?);
                let (z_min, z_max) = (z0.min(z1).max(-radius), z0.max(z1).min(radius));
                let phi_max = f(p.float("phimax", 360.0))?.clamp(0.0, 360.0);
                if !(radius > 0.0 && radius.is_finite()) {
                    return Err(self.parser.error(d.at, format!("a sphere's radius must be > 0, got {radius}")));
                }
                if z_min <= -radius && z_max >= radius && phi_max >= 360.0 {
                    if reverse {
                        self.warn(d.at, "ReverseOrientation on a sphere is ignored (glint's spheres face out)");
                    }
                    let material = self.shape_material(alpha, d.at);
                    // glint's sphere has its pole on +y (u about +y from +x); pbrt's on +z (u
                    // about +z from +x): swapping y and z gives pbrt's uv, hence its textures.
                    let swap = Mat4::from_cols(Vec4::X, Vec4::Z, Vec4::Y, Vec4::W);
                    let desc = ShapeDesc::Sphere { interior: None, exterior: None, center: [0.0; 3], radius, material, transform: vec![matrix_op(swap), matrix_op(ctm)], name: Some(self.shape_name(kind, d.at)) };
                    return self.push_shape(d.at, desc);
                }
                shapes::partial_sphere(radius, z_min, z_max, phi_max.to_radians())
            }
            "disk" => {
                let (h, r, inner, phi) = (f(p.float("height", 0.0))?, f(p.float("radius", 1.0))?, f(p.float("innerradius", 0.0))?, f(p.float("phimax", 360.0))?);
                if !(r > 0.0 && inner >= 0.0 && inner < r) {
                    return Err(self.parser.error(d.at, format!("a disk needs 0 ≤ innerradius < radius, got {inner} and {r}")));
                }
                shapes::disk(h, r, inner, phi.clamp(0.0, 360.0).to_radians())
            }
            "cylinder" => {
                let (r, z0, z1, phi) = (f(p.float("radius", 1.0))?, f(p.float("zmin", -1.0))?, f(p.float("zmax", 1.0))?, f(p.float("phimax", 360.0))?);
                if !(r > 0.0 && z0 != z1) {
                    return Err(self.parser.error(d.at, "a cylinder needs radius > 0 and zmin ≠ zmax"));
                }
                shapes::cylinder(r, z0.min(z1), z0.max(z1), phi.clamp(0.0, 360.0).to_radians())
            }
            "trianglemesh" => self.triangle_mesh(&p)?,
            "bilinearmesh" => self.bilinear_mesh(&p)?,
            "loopsubdiv" => {
                let levels = p.int("levels", 3).map_err(|f| self.fail(f))?;
                if !(0..=8).contains(&levels) {
                    return Err(self.parser.error(self.param_at(&p, "levels"), format!("`levels` must be 0 to 8, got {levels}")));
                }
                let mesh = self.triangle_mesh(&p)?;
                if mesh.normals.is_some() || mesh.uvs.is_some() {
                    self.warn(d.at, "a loopsubdiv's `N` and `uv` are not carried through subdivision (as in pbrt)");
                }
                // Each level quadruples the triangles; about 100 bytes each while subdividing.
                let needed = (mesh.indices.len() as u64).saturating_mul(100 << (2 * levels));
                if needed > crate::limits::memory_limit() {
                    return Err(self.parser.error(
                        self.param_at(&p, "levels"),
                        format!(
                            "{} levels of subdivision of {} triangles take about {}, more than the memory limit of {} ({})",
                            levels,
                            mesh.indices.len(),
                            crate::limits::describe(needed),
                            crate::limits::describe(crate::limits::memory_limit()),
                            crate::limits::RAISE
                        ),
                    ));
                }
                let positions: Vec<Vec3> = mesh.positions.iter().map(|&q| q.into()).collect();
                shapes::loop_subdivide(&positions, &mesh.indices, levels as u32).map_err(|m| self.parser.error(d.at, m))?
            }
            "plymesh" => {
                let file = p.string("filename").map_err(|f| self.fail(f))?.ok_or_else(|| self.parser.error(d.at, "a plymesh needs a `filename`"))?;
                if p.list.iter().any(|x| x.name == "displacement") {
                    return Err(self.parser.error(self.param_at(&p, "displacement"), "displacement is not supported"));
                }
                p.ignore(&["edgelength"]);
                // Read here rather than by the builder: pbrt faces a mesh to its normals.
                let bytes = self.source.read(&file).map_err(|m| self.parser.error(d.at, m))?;
                let mesh = crate::mesh::read_mesh(&file, &bytes).map_err(|m| self.parser.error(d.at, format!("`{file}`: {m}")))?;
                MeshData {
                    positions: mesh.positions.iter().map(|q| q.to_array()).collect(),
                    indices: mesh.indices,
                    normals: mesh.normals.map(|ns| ns.iter().map(|n| n.to_array()).collect()),
                    uvs: mesh.uvs.map(|uv| uv.iter().map(|t| t.to_array()).collect()),
                    // pbrt reads no other vertex values.
                    colors: None,
                }
            }
            other => {
                return Err(self.parser.error(
                    d.at,
                    format!("shape `{other}` is not supported; glint reads trianglemesh, plymesh, sphere, disk, cylinder, bilinearmesh, loopsubdiv and curve"),
                ))
            }
        };
        if data.indices.is_empty() {
            self.warn(d.at, format!("the {kind} has no triangles and is left out"));
            return Ok(());
        }
        // pbrt negates a shape's normals under ReverseOrientation, then faces the surface to
        // them. Its Loop surfaces face the way their limit normals Cross(S, T) point, and it
        // walks each one-ring clockwise about the winding: against the winding.
        let reverse = reverse ^ (kind == "loopsubdiv");
        if reverse {
            data.normals.iter_mut().flatten().for_each(|n| *n = (-Vec3::from(*n)).to_array());
        }
        orient(&mut data, reverse);
        let smooth = data.normals.is_some() || kind == "loopsubdiv";
        let material = self.shape_material(alpha, d.at);
        let desc = ShapeDesc::Mesh {
            interior: None,
            exterior: None,
            file: None,
            data: Some(data),
            shape_index: 0,
            smooth,
            flip_v: false,
            compute_normals: kind == "loopsubdiv",
            material,
            transform: vec![matrix_op(ctm)],
            name: Some(self.shape_name(kind, d.at)),
        };
        self.push_shape(d.at, desc)
    }

    /// The current material, cut out by `alpha` where given, wrapped as an emitter under an
    /// area light.
    fn shape_material(&mut self, alpha: Option<FractionDesc>, at: At) -> String {
        let mut material = self.current_material();
        if let Some(opacity) = alpha {
            // One mask per material and alpha, however many shapes share them.
            let key = (material.clone(), format!("{opacity:?}"));
            material = match self.alpha_masks.get(&key) {
                Some(masked) => masked.clone(),
                None => {
                    let masked = format!("{material}, cut out by alpha {}", self.alpha_masks.len() + 1);
                    let desc = MaterialDesc::Mask { opacity: Some(opacity), material };
                    self.scene.materials.insert(masked.clone(), Located { value: desc, span: None });
                    self.alpha_masks.insert(key, masked.clone());
                    masked
                }
            };
        }
        match self.state.area_light.clone() {
            Some(light) if self.defining.is_none() => {
                let name = self.unique("area light", at);
                let desc = MaterialDesc::Emitter {
                    radiance: ColorDesc::Rgb(light.radiance),
                    two_sided: light.two_sided,
                    material,
                };
                self.scene.materials.insert(name.clone(), Located { value: desc, span: None });
                name
            }
            _ => material,
        }
    }

    /// pbrt's `curve`: cubic (or quadratic) Bézier or B-spline segments of points `P`, their
    /// width running from `width0` to `width1` along the curve, as glint's round curves in
    /// cubic Bézier form. pbrt's `cylinder` curves are flat ribbons shaded as if round, which a
    /// tube of the same width is; `flat` and `ribbon` ones (facing the ray, or turned by `N`)
    /// are rendered round too, with a warning. Widths scale with the transform, as pbrt's.
    fn curve(&mut self, d: &Directive, p: &Params, alpha: Option<FractionDesc>) -> Result<()> {
        let f = |r: std::result::Result<f32, Failure>| r.map_err(|x| self.fail(x));
        let points: Vec<Vec3> = p
            .triples("P")
            .map_err(|x| self.fail(x))?
            .ok_or_else(|| self.parser.error(d.at, "a curve needs its control points `P`"))?
            .into_iter()
            .map(Vec3::from)
            .collect();
        let degree = p.int("degree", 3).map_err(|x| self.fail(x))?;
        let basis = p.string("basis").map_err(|x| self.fail(x))?.unwrap_or_else(|| "bezier".into());
        let kind = p.string("type").map_err(|x| self.fail(x))?.unwrap_or_else(|| "flat".into());
        let width = f(p.float("width", 1.0))?;
        let (width0, width1) = (f(p.float("width0", width))?, f(p.float("width1", width))?);
        p.ignore(&["splitdepth", "N"]);
        if !(width0 >= 0.0 && width1 >= 0.0 && width0.is_finite() && width1.is_finite()) {
            return Err(self.parser.error(d.at, format!("a curve's widths must be ≥ 0, got {width0} and {width1}")));
        }
        if kind != "cylinder" {
            self.warn(
                d.at,
                format!("a `{kind}` curve is rendered as a round tube of its width (pbrt's is a flat ribbon {}); shading differs, the outline does not", if kind == "ribbon" { "turned by its normals" } else { "facing the ray" }),
            );
        }
        // Each segment's cubic Bézier control points.
        let segments: Vec<[Vec3; 4]> = match (basis.as_str(), degree) {
            ("bezier", 3) if points.len() >= 4 && (points.len() - 1).is_multiple_of(3) => (0..points.len() - 1)
                .step_by(3)
                .map(|i| [points[i], points[i + 1], points[i + 2], points[i + 3]])
                .collect(),
            ("bezier", 2) if points.len() >= 3 && (points.len() - 1).is_multiple_of(2) => {
                (0..points.len() - 1).step_by(2).map(|i| elevate([points[i], points[i + 1], points[i + 2]])).collect()
            }
            ("bspline", 3) if points.len() >= 4 => (0..points.len() - 3)
                .map(|i| {
                    let [p0, p1, p2, p3] = [points[i], points[i + 1], points[i + 2], points[i + 3]];
                    [
                        (p0 + 4.0 * p1 + p2) / 6.0,
                        (2.0 * p1 + p2) / 3.0,
                        (p1 + 2.0 * p2) / 3.0,
                        (p1 + 4.0 * p2 + p3) / 6.0,
                    ]
                })
                .collect(),
            ("bspline", 2) if points.len() >= 3 => (0..points.len() - 2)
                .map(|i| {
                    let [p0, p1, p2] = [points[i], points[i + 1], points[i + 2]];
                    elevate([(p0 + p1) / 2.0, p1, (p1 + p2) / 2.0])
                })
                .collect(),
            ("bezier" | "bspline", 2 | 3) => {
                return Err(self.parser.error(
                    self.param_at(p, "P"),
                    format!("`P` holds {} point(s), which make no {basis} segments of degree {degree}", points.len()),
                ))
            }
            _ => {
                return Err(self.parser.error(
                    d.at,
                    format!("a curve's basis is bezier or bspline and its degree 2 or 3, got {basis} and {degree}"),
                ))
            }
        };
        // Widths scale with the transform (by its mean scale where it is not uniform).
        let ctm = self.state.ctm;
        let scale = ctm.determinant().abs().cbrt();
        let n = segments.len() as f32;
        let radius = |at: f32| 0.5 * scale * (width0 + (width1 - width0) * at);
        let mut curve: Vec<[f32; 4]> = Vec::with_capacity(3 * segments.len() + 1);
        for (s, segment) in segments.iter().enumerate() {
            let (ra, rb) = (radius(s as f32 / n), radius((s + 1) as f32 / n));
            for (k, point) in segment.iter().enumerate().skip(usize::from(s > 0)) {
                let r = ra + (rb - ra) * k as f32 / 3.0;
                curve.push([point.x, point.y, point.z, r]);
            }
        }
        let material = self.shape_material(alpha, d.at);
        let desc = ShapeDesc::Curves {
            basis: Some("bezier".into()),
            file: None,
            data: Some(vec![curve]),
            material,
            transform: vec![matrix_op(ctm)],
            name: Some(self.shape_name("curve", d.at)),
        };
        self.push_shape(d.at, desc)
    }

    /// A shape's name in messages and explanations: its directive and where it stands.
    fn shape_name(&self, kind: &str, at: At) -> String {
        format!("Shape \"{kind}\" at {}", self.parser.place(at))
    }

    fn push_shape(&mut self, at: At, mut desc: ShapeDesc) -> Result<()> {
        // Only a transition (inside ≠ outside) changes a ray's medium, as in pbrt; a shape in
        // one medium on both sides keeps whatever medium the ray is in.
        let (inside, outside) = self.state.media.clone();
        if let (Some((interior, exterior)), true) = (desc.media_mut(), inside != outside) {
            (*interior, *exterior) = (inside, outside);
        }
        let shape = Located { value: desc, span: None };
        match &mut self.defining {
            Some((_, shapes, _)) => {
                shapes.push(shape);
                if self.state.area_light.is_some() {
                    self.warn(
                        at,
                        "an area light on a shape inside an object definition is ignored (as pbrt ignores it)",
                    );
                }
            }
            None => self.scene.shapes.push(shape),
        }
        Ok(())
    }

    fn triangle_mesh(&self, p: &Params) -> Result<MeshData> {
        let positions = p
            .triples("P")
            .map_err(|f| self.fail(f))?
            .ok_or_else(|| self.parser.error(p.at, "a triangle mesh needs its vertices `\"point3 P\"`"))?;
        let indices = match p.ints("indices").map_err(|f| self.fail(f))? {
            Some((ints, at)) => {
                if ints.len() % 3 != 0 {
                    return Err(self
                        .parser
                        .error(at, format!("`indices` holds triangles: a multiple of 3 numbers, got {}", ints.len())));
                }
                let n = positions.len() as i64;
                if let Some(bad) = ints.iter().find(|&&i| i < 0 || i >= n) {
                    return Err(self.parser.error(at, format!("index {bad} refers to no vertex (there are {n})")));
                }
                ints.chunks_exact(3).map(|c| [c[0] as u32, c[1] as u32, c[2] as u32]).collect()
            }
            None if positions.len() == 3 => vec![[0, 1, 2]],
            None => {
                return Err(self.parser.error(
                    p.at,
                    "a triangle mesh needs `\"integer indices\"` (only a single triangle may leave them out)",
                ))
            }
        };
        let normals = p.triples("N").map_err(|f| self.fail(f))?;
        let uvs = p.pairs("uv").map_err(|f| self.fail(f))?.or(p.pairs("st").map_err(|f| self.fail(f))?);
        p.ignore(&["S", "faceIndices"]);
        for (what, len) in [("N", normals.as_ref().map(Vec::len)), ("uv", uvs.as_ref().map(Vec::len))] {
            if let Some(len) = len {
                if len != positions.len() {
                    return Err(self.parser.error(
                        self.param_at(p, what),
                        format!("`{what}` has {len} entries for {} vertices", positions.len()),
                    ));
                }
            }
        }
        Ok(MeshData { positions, indices, normals, uvs, colors: None })
    }

    fn bilinear_mesh(&self, p: &Params) -> Result<MeshData> {
        let positions = p
            .triples("P")
            .map_err(|f| self.fail(f))?
            .ok_or_else(|| self.parser.error(p.at, "a bilinear mesh needs `\"point3 P\"`"))?;
        let indices: Vec<i64> = match p.ints("indices").map_err(|f| self.fail(f))? {
            Some((ints, _)) => ints,
            None if positions.len() == 4 => vec![0, 1, 2, 3],
            None => return Err(self.parser.error(p.at, "a bilinear mesh needs `\"integer indices\"`, four per patch")),
        };
        if !indices.len().is_multiple_of(4) || indices.iter().any(|&i| i < 0 || i as usize >= positions.len()) {
            return Err(self.parser.error(
                self.param_at(p, "indices"),
                "`indices` must be four vertex numbers per patch, each naming a vertex",
            ));
        }
        let normals = p.triples("N").map_err(|f| self.fail(f))?;
        let uvs = p.pairs("uv").map_err(|f| self.fail(f))?;
        for (what, len) in [("N", normals.as_ref().map(Vec::len)), ("uv", uvs.as_ref().map(Vec::len))] {
            if let Some(len) = len {
                if len != positions.len() {
                    return Err(self.parser.error(
                        self.param_at(p, what),
                        format!("`{what}` has {len} entries for {} vertices", positions.len()),
                    ));
                }
            }
        }
        // Curved patches are cut finer the fewer there are: 16 × 16 cells each up to 8,192
        // patches, then fewer, about four million triangles in all.
        let patches = indices.len() / 4;
        let cells = ((2_097_152 / patches.max(1)) as f64).sqrt().clamp(1.0, 16.0) as usize;
        let mut data = MeshData::default();
        for patch in indices.chunks_exact(4) {
            let at = |k: usize| patch[k] as usize;
            let corners = [0, 1, 2, 3].map(|k| Vec3::from(positions[at(k)]));
            let patch_uvs = match &uvs {
                Some(uv) => [0, 1, 2, 3].map(|k| Vec2::from(uv.get(at(k)).copied().unwrap_or_default())),
                None => [Vec2::ZERO, Vec2::X, Vec2::Y, Vec2::ONE],
            };
            let patch_normals = normals
                .as_ref()
                .map(|n| [0, 1, 2, 3].map(|k| Vec3::from(n.get(at(k)).copied().unwrap_or([0.0, 0.0, 1.0]))));
            shapes::append(&mut data, shapes::bilinear_patch(corners, patch_uvs, patch_normals, cells));
        }
        Ok(data)
    }
}

/// Winds `data`'s triangles so that glint's normal ((p1 − p0) × (p2 − p0) in the shape's own
/// space, which glint keeps through any transform, mirroring or not) is pbrt's: with
/// per-vertex normals, the side they face; without, the winding's own, turned over by
/// `ReverseOrientation`. (pbrt flips a mirrored shape's normal back too: the same rule.)
fn orient(data: &mut MeshData, reverse: bool) {
    let p = |i: u32, data: &MeshData| Vec3::from(data.positions[i as usize]);
    for k in 0..data.indices.len() {
        let [a, b, c] = data.indices[k];
        let flip = match &data.normals {
            Some(normals) => {
                let cross = (p(b, data) - p(a, data)).cross(p(c, data) - p(a, data));
                let n: Vec3 = [a, b, c].iter().map(|&i| Vec3::from(normals[i as usize])).sum();
                cross.dot(n) < 0.0
            }
            None => reverse,
        };
        if flip {
            data.indices[k] = [a, c, b];
        }
    }
}

/// A quadratic Bézier's control points as a cubic's (degree elevation).
fn elevate([c0, c1, c2]: [Vec3; 3]) -> [Vec3; 4] {
    [c0, c0 + (2.0 / 3.0) * (c1 - c0), c1 + (1.0 / 3.0) * (c2 - c1), c2]
}

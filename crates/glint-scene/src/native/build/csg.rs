//! CSG trees of the `csg` shape: each node's operation over its operands, each operand
//! a closed solid checked and placed by its own transform after its node's.

use std::ops::Range;

use glint_core::geometry::Transform;
use glint_core::materials::Material;
use glint_core::shapes::{CsgOperation, CsgSolid, CsgTree, Instance, Shape};
use glint_core::Named;

use super::checks::quoted;
use super::shapes::{box_shape, material_index, sphere_shape, MeshLibrary};
use super::transform::build_transform;
use super::Context;
use crate::error::{did_you_mean, SceneError};
use crate::native::schema::*;
use crate::source::Source;

/// What a CSG operand's checks need besides the operand: the scene's materials and named
/// meshes, where files come from, and the shape's label for messages.
pub(super) struct OperandContext<'a, 'b, 'c> {
    pub(super) cx: &'a Context<'a>,
    pub(super) materials: &'a [(String, Material)],
    pub(super) library: &'a mut MeshLibrary<'b>,
    pub(super) source: &'a Source<'c>,
    pub(super) warnings: &'a mut Vec<String>,
    pub(super) label: &'a str,
}

/// A CSG node's operation over its operands, each checked and placed by its own transform
/// composed after the node's (`outer`); `material` is the node's, for operands without one.
pub(super) fn csg_tree(
    oc: &mut OperandContext,
    span: &Option<Range<usize>>,
    operation: &str,
    operands: &[OperandDesc],
    outer: Option<Transform>,
    material: Option<u32>,
    path: &str,
) -> Result<CsgTree, SceneError> {
    let (cx, label) = (oc.cx, oc.label);
    let at = |key: &str, m: String| cx.error(span, Some(key), format!("{label}: {path}{m}"));
    let operation = CsgOperation::from_name(operation).ok_or_else(|| {
        let names: Vec<&str> = CsgOperation::ALL.iter().map(|o| o.name()).collect();
        let hint = did_you_mean(operation, names.iter().copied());
        at("operation", format!("unknown CSG operation `{operation}`, expected one of {}{hint}", quoted(&names)))
    })?;
    if operands.len() < 2 {
        let message = format!("a {} needs at least two operands, got {}", operation.name(), operands.len());
        return Err(at("operands", message));
    }
    let mut trees = Vec::with_capacity(operands.len());
    for (k, entry) in operands.iter().enumerate() {
        trees.push(csg_operand(oc, span, entry, outer, material, &format!("{path}operands[{k}]: "))?);
    }
    Ok(CsgTree::Combine(operation, trees))
}

fn csg_operand(
    oc: &mut OperandContext,
    span: &Option<Range<usize>>,
    operand: &OperandDesc,
    outer: Option<Transform>,
    inherited: Option<u32>,
    path: &str,
) -> Result<CsgTree, SceneError> {
    let cx = oc.cx;
    let label = oc.label;
    let at = |key: &str, m: String| cx.error(span, Some(key), format!("{label}: {path}{m}"));
    let (material, transform_ops) = match operand {
        OperandDesc::Sphere { material, transform, .. }
        | OperandDesc::Box { material, transform, .. }
        | OperandDesc::Instance { material, transform, .. }
        | OperandDesc::Csg { material, transform, .. } => (material, transform),
    };
    let material = match material {
        Some(name) => Some(material_index(oc.materials, name).map_err(|m| at("material", m))?),
        None => inherited,
    };
    let own = build_transform(transform_ops).map_err(|m| at("transform", m))?;
    let transform = match (outer, own) {
        (Some(o), Some(t)) => Some(o.after(&t)),
        (o, t) => o.or(t),
    };
    let shape = match operand {
        OperandDesc::Sphere { center, radius, .. } => sphere_shape(*center, *radius).map_err(|(k, m)| at(k, m))?,
        OperandDesc::Box { min, max, .. } => box_shape(*min, *max).map_err(|(k, m)| at(k, m))?,
        OperandDesc::Instance { mesh, .. } => {
            let geometry = oc.library.get(cx, mesh, oc.source, oc.warnings, |m| at("mesh", m))?;
            if geometry.objects().len() != 1
                || !matches!(&geometry.objects()[0].shape, Shape::Mesh(m) if m.enclosed_volume().is_some_and(|v| v != 0.0))
            {
                return Err(at(
                    "mesh",
                    format!("mesh `{mesh}` is not closed: a CSG operand must bound a solid (every edge shared by exactly two triangles wound the same way)"),
                ));
            }
            Shape::Instance(Instance { geometry })
        }
        OperandDesc::Csg { operation, operands, .. } => {
            return csg_tree(oc, span, operation, operands, transform, material, path);
        }
    };
    Ok(CsgTree::Solid(Box::new(CsgSolid { shape, transform, material })))
}

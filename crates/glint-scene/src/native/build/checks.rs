//! The checks every value of a scene goes through: finite and not too large, non-negative
//! colours, positive numbers, and named choices (an unknown name lists the known ones and
//! suggests the closest).

use glam::Vec3;
use glint_core::Named;

use super::Context;
use crate::error::{did_you_mean, SceneError};
use crate::native::schema::Vector;

/// The largest coordinate (or length) a scene may hold: squared, as lengths and the sphere's
/// quadratic square it, it must stay within f32 (3.4e38), with room for sums of three. A
/// sphere of radius 1e38 rendered as background only (r² was infinite), a camera at
/// −1e38 was told its `look_at` equals its `position`.
pub(super) const MAX_COORDINATE: f32 = 1e18;

pub(super) fn finite(v: Vector) -> Result<Vec3, String> {
    let v3 = Vec3::from(v);
    if !v3.is_finite() {
        Err(format!("expected finite numbers, got {v:?}"))
    } else if v3.abs().max_element() > MAX_COORDINATE {
        Err(format!("expected numbers of magnitude at most {MAX_COORDINATE:e} (their squares must fit in 32-bit floats), got {v:?}"))
    } else {
        Ok(v3)
    }
}

pub(in crate::native) fn non_negative(v: Vector) -> Result<Vec3, String> {
    let v3 = finite(v)?;
    if v3.min_element() < 0.0 {
        return Err(format!("colours must be ≥ 0, got {v:?}"));
    }
    Ok(v3)
}

pub(in crate::native) fn positive(x: f32) -> Result<(), String> {
    if x.is_finite() && x > 0.0 {
        Ok(())
    } else {
        Err(format!("must be a finite number > 0, got {x}"))
    }
}

/// A named choice (`Named`): an unknown name is an error listing the choices, with a guess.
pub(super) fn by_name<T: Named>(cx: &Context, key: &str, what: &str, value: &str) -> Result<T, SceneError> {
    T::from_name(value).ok_or_else(|| {
        let names: Vec<&str> = T::ALL.iter().map(|k| k.name()).collect();
        let hint = did_you_mean(value, names.iter().copied());
        cx.error_at_key(key, format!("unknown {what} `{value}`, expected one of {}{hint}", quoted(&names)))
    })
}

pub(in crate::native) fn quoted(names: &[&str]) -> String {
    names.iter().map(|n| format!("`{n}`")).collect::<Vec<_>>().join(", ")
}

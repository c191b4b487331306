//! A render's identity: what makes its image what it is, hashed into the fingerprint that a
//! checkpoint records (a checkpoint resumes only the render that wrote it) and that a partial
//! render carries as `glint:identity` (parts merge only with parts of the same render). One
//! identity for every front end: a part rendered from Python merges with one from the CLI.

use std::hash::Hash;
use std::path::PathBuf;

use glint_core::filter::Filter;
use glint_core::integrators::{IntegratorKind, IntegratorSettings};
use glint_core::lights::TriangleSampling;
use glint_core::sampling::SamplerKind;
use glint_core::shapes::IntersectMethods;

use super::SceneSource;
use crate::checkpoint;

/// Everything that makes a render's image what it is, but the seed (which a checkpoint
/// records by itself and a part spells out): a checkpoint is resumed, and parts are merged,
/// only by renders with the same identity.
#[derive(Hash, Debug)]
pub struct RenderIdentity<'a> {
    /// Each of the scene's files by content (`Job::scene_contents`); empty when no
    /// checkpoint or part needs the identity (the files are then not read again).
    pub scene_contents: &'a [u8],
    /// Mitsuba's `-D` parameters.
    pub defines: &'a [(String, String)],
    pub kind: IntegratorKind,
    /// Every setting but the wavefront, which gives the same image (its `Hash`).
    pub integrator: IntegratorSettings,
    pub methods: IntersectMethods,
    pub width: u32,
    pub height: u32,
    pub filter: Filter,
    pub sampler: SamplerKind,
    /// A stratified render's strata depend on its sample count (a sample range's are open).
    pub strata_spp: Option<u32>,
    pub triangle_sampling: TriangleSampling,
}

impl RenderIdentity<'_> {
    /// The identity as one number, the same in every build (FNV-1a).
    pub fn fingerprint(&self) -> u64 {
        checkpoint::fingerprint_of(self)
    }
}

/// The scene's files by content, in order: each file's FNV-1a hash of its contents and length
/// (a file that cannot be read now counts as empty). A description built in memory counts
/// by its JSON text in place of its name; the built-in scene by its name.
pub(super) fn scene_contents(source: &SceneSource, inputs: &[PathBuf]) -> Vec<u8> {
    match source {
        SceneSource::BuiltIn => b"<built-in default scene>".to_vec(),
        // Without the default light a glTF model renders another image; marked only when
        // asked for, so that every other render keeps its fingerprint.
        SceneSource::File { no_default_light, .. } => {
            let mut contents = inputs_fingerprint(inputs);
            if *no_default_light {
                contents.extend_from_slice(b"<no default light>");
            }
            contents
        }
        SceneSource::Description { json, .. } => {
            let text = json.text.as_bytes();
            let own = checkpoint::fingerprint(&[text, &(text.len() as u64).to_le_bytes()]).to_le_bytes();
            // The first input is the description's name, not a file.
            own.into_iter().chain(inputs_fingerprint(inputs.get(1..).unwrap_or_default())).collect()
        }
    }
}

/// A fingerprint of each file, in order: its contents' FNV-1a hash with its length.
fn inputs_fingerprint(inputs: &[PathBuf]) -> Vec<u8> {
    // Through the scene readers' bounded reader: a file past the memory limit (a glTF buffer
    // far longer than its byteLength, of which the reader took only that) is not read whole
    // again here; its length still counts.
    inputs
        .iter()
        .flat_map(|path| {
            let length = std::fs::metadata(path).map(|m| m.len()).unwrap_or_default().to_le_bytes();
            let bytes = glint_scene::read_file(path, u64::MAX).unwrap_or_default();
            checkpoint::fingerprint(&[&bytes, &length]).to_le_bytes()
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A render without the default light is another render; with it, the scene's contents are
    /// those of before the option existed.
    #[test]
    fn the_default_light_left_out_changes_the_identity() {
        let file = |no_default_light| SceneSource::File {
            path: "model.glb".into(),
            defines: Vec::new(),
            search_path: Vec::new(),
            no_default_light,
        };
        let inputs = [PathBuf::from("no-such-model.glb")];
        let (lit, unlit) = (scene_contents(&file(false), &inputs), scene_contents(&file(true), &inputs));
        assert_eq!(lit, inputs_fingerprint(&inputs));
        assert_ne!(identity(&lit, &[]).fingerprint(), identity(&unlit, &[]).fingerprint());
    }

    fn identity<'a>(contents: &'a [u8], defines: &'a [(String, String)]) -> RenderIdentity<'a> {
        RenderIdentity {
            scene_contents: contents,
            defines,
            kind: IntegratorKind::Path,
            integrator: IntegratorSettings::default(),
            methods: IntersectMethods::default(),
            width: 64,
            height: 48,
            filter: Filter::Box,
            sampler: SamplerKind::Independent,
            strata_spp: None,
            triangle_sampling: TriangleSampling::Area,
        }
    }

    /// The fingerprint of a fixed identity, written down: a change to what the identity
    /// hashes, or how, shows here (and would make old checkpoints and parts foreign).
    #[test]
    fn the_fingerprint_is_stable_and_sees_every_field() {
        let base = identity(b"scene", &[]);
        let fingerprint = base.fingerprint();
        assert_eq!(fingerprint, 0xe8cc_af4e_b244_9b0f, "{fingerprint:#018x}");
        let defines = [("spp".to_string(), "4".to_string())];
        let changed: Vec<RenderIdentity> = vec![
            identity(b"scenf", &[]),
            identity(b"scene", &defines),
            RenderIdentity { kind: IntegratorKind::VolPath, ..identity(b"scene", &[]) },
            RenderIdentity {
                integrator: IntegratorSettings { max_depth: 6, ..Default::default() },
                ..identity(b"scene", &[])
            },
            RenderIdentity {
                methods: IntersectMethods { sphere: glint_core::shapes::SphereMethod::Geometric, ..Default::default() },
                ..identity(b"scene", &[])
            },
            RenderIdentity { width: 65, ..identity(b"scene", &[]) },
            RenderIdentity { height: 47, ..identity(b"scene", &[]) },
            RenderIdentity { filter: Filter::Gaussian, ..identity(b"scene", &[]) },
            RenderIdentity { sampler: SamplerKind::Sobol, ..identity(b"scene", &[]) },
            RenderIdentity { strata_spp: Some(4), ..identity(b"scene", &[]) },
            RenderIdentity { triangle_sampling: TriangleSampling::SolidAngle, ..identity(b"scene", &[]) },
        ];
        for (k, other) in changed.iter().enumerate() {
            assert_ne!(other.fingerprint(), fingerprint, "change {k}: {other:?}");
        }
        // The wavefront gives the same image: the same identity.
        let scalar = RenderIdentity {
            integrator: IntegratorSettings { wavefront: false, ..Default::default() },
            ..identity(b"scene", &[])
        };
        assert_eq!(scalar.fingerprint(), fingerprint);
    }
}

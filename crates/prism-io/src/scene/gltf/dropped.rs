//! What a glTF file holds that prism reads but does not render, said once per file as a
//! warning (which `--strict` makes an error), so that nothing is dropped in silence.

use gltf::json::mesh::Semantic;
use gltf::json::texture::WrappingMode;
use gltf::json::validation::Checked;
use gltf::json::Root;

/// The extensions the loader reads and renders.
const RENDERED_EXTENSIONS: [&str; 5] = [
    "KHR_lights_punctual",
    "KHR_materials_transmission",
    "KHR_materials_ior",
    "KHR_materials_emissive_strength",
    "KHR_mesh_quantization",
];

/// One warning naming every feature of `root` that the picture will not show, with how
/// many materials, meshes or items use it; None when there is none.
pub(super) fn warning(root: &Root) -> Option<String> {
    let mut dropped: Vec<String> = Vec::new();
    let mut count = |what: &str, n: usize| {
        if n > 0 {
            dropped.push(format!("{what} ({n})"));
        }
    };
    let materials = &root.materials;
    let pbr = |f: fn(&gltf::json::Material) -> bool| materials.iter().filter(|m| f(m)).count();
    count(
        "textures reading several TEXCOORD sets, all drawn with the first one's",
        pbr(|m| {
            let sets = super::materials::texture_sets(m);
            sets.iter().any(|&s| s != sets[0])
        }),
    );
    count(
        "texture samplers that clamp or mirror, drawn repeating",
        root.samplers
            .iter()
            .filter(|s| {
                [&s.wrap_s, &s.wrap_t]
                    .iter()
                    .any(|w| !matches!(w, Checked::Valid(WrappingMode::Repeat)))
            })
            .count(),
    );
    count(
        "alphaMode MASK or BLEND, drawn opaque",
        pbr(|m| {
            !matches!(
                m.alpha_mode,
                Checked::Valid(gltf::json::material::AlphaMode::Opaque)
            )
        }),
    );
    let primitives = || root.meshes.iter().flat_map(|m| m.primitives.iter());
    let with = |s: Semantic| {
        primitives()
            .filter(|p| p.attributes.contains_key(&Checked::Valid(s.clone())))
            .count()
    };
    count("COLOR_0 vertex colours", with(Semantic::Colors(0)));
    count(
        "morph targets, shown unmorphed",
        primitives().filter(|p| p.targets.is_some()).count(),
    );
    count("skins, shown in the bind pose", root.skins.len());
    count("animations, shown at rest", root.animations.len());
    // Extensions the file uses that the loader does not read (KHR_texture_transform,
    // KHR_materials_clearcoat, …): named one by one, as the file names them.
    for name in &root.extensions_used {
        if !RENDERED_EXTENSIONS.contains(&name.as_str()) {
            dropped.push(format!("extension {name}"));
        }
    }
    (!dropped.is_empty())
        .then(|| format!("read but not rendered as authored: {}", dropped.join(", ")))
}

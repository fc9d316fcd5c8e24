//! What a glTF file holds that prism reads but does not render, said once per file as a
//! warning (which `--strict` makes an error), so that nothing is dropped in silence.

use gltf::json::mesh::Semantic;
use gltf::json::validation::Checked;
use gltf::json::Root;

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
        "metallicRoughnessTexture, averaged to one value per material",
        pbr(|m| {
            m.pbr_metallic_roughness
                .metallic_roughness_texture
                .is_some()
        }),
    );
    count(
        "emissiveTexture, averaged to one colour per material",
        pbr(|m| m.emissive_texture.is_some()),
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
    count(
        "TANGENT attributes, normal maps use each triangle's uv frame",
        with(Semantic::Tangents),
    );
    count("COLOR_0 vertex colours", with(Semantic::Colors(0)));
    count(
        "morph targets, shown unmorphed",
        primitives().filter(|p| p.targets.is_some()).count(),
    );
    count("skins, shown in the bind pose", root.skins.len());
    count("animations, shown at rest", root.animations.len());
    (!dropped.is_empty())
        .then(|| format!("read but not rendered as authored: {}", dropped.join(", ")))
}

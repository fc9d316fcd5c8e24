//! MTL materials as prism's Whitted material. The MTL illumination models (`illum`) say
//! which terms are on; the colours' channels are averaged where prism has one weight (its
//! highlight and the mirror ray are white, as in Whitted's model); the transmission filter
//! `Tf` stays a colour. docs/formats.md has the
//! table; the comments below say why each choice.

use prism::math::Color;
use prism::shading::{BumpMap, FresnelMode, Highlight, ImageTexture, Material, NormalMap, Texture};

/// What prism reads from an MTL material beside tobj.
#[derive(Clone, Debug, Default)]
pub(super) struct Extras {
    /// `map_Kd`: the diffuse colour's image.
    pub texture: Option<ImageTexture>,
    /// `Tf`: the transmission filter.
    pub tf: Option<Color>,
    /// `Tr`: transparency, 1 − d.
    pub tr: Option<f32>,
    /// `Ke`: the emitted radiance (an area light).
    pub ke: Option<Color>,
    /// `norm`: a tangent-space normal map.
    pub normal_map: Option<NormalMap>,
    /// `bump` or `map_Bump`: a height map.
    pub bump_map: Option<BumpMap>,
}

fn mean(c: [f32; 3]) -> f32 {
    (c[0] + c[1] + c[2]) / 3.0
}

/// The prism material for an MTL material.
pub(super) fn whitted(m: &tobj::Material, extras: &Extras) -> Material {
    let d = Material::default();
    let illum = m.illumination_model.unwrap_or(2);
    let ks = m.specular.map_or(0.0, mean);
    let ior = m.optical_density.unwrap_or(d.ior);
    // `d` wins over `Tr` when a file gives both (d is the standard statement).
    let opacity = m.dissolve.or(extras.tr.map(|t| 1.0 - t)).unwrap_or(1.0);

    let (color, mut diffuse) = match &extras.texture {
        // map_Kd multiplies Kd; prism's textures carry no tint, so Kd's mean weighs it.
        Some(image) => (Texture::Image(image.clone()), m.diffuse.map_or(1.0, mean)),
        None => (
            Texture::Solid(m.diffuse.map_or(Color::splat(0.8), Color::from_array)),
            1.0,
        ),
    };
    // prism's ambient term is Ia·ka·C with C the diffuse colour, so Ka gives only a weight.
    let mut ambient = m.ambient.map_or(d.ambient, mean);

    // 0 (colour without lighting) has no counterpart in prism and is lit like 1.
    let specular = if illum >= 2 { ks } else { 0.0 };
    // 3, 4, 5, 6, 7 trace a mirror ray weighted by Ks; 8 (reflection without tracing)
    // can only be traced in prism.
    let reflect = if matches!(illum, 3..=8) { ks } else { 0.0 };
    let fresnel = if matches!(illum, 5 | 7) {
        FresnelMode::Exact
    } else {
        FresnelMode::Off
    };
    let (transmit, ior) = if matches!(illum, 6 | 7) {
        // Refraction: the MTL equation's (1 − Ks)·Tf·It term, per channel; d does not apply.
        let tf = extras.tf.unwrap_or(Color::ONE);
        ((1.0 - ks).max(0.0) * tf, ior)
    } else if opacity < 1.0 {
        // Dissolve: light passes straight through (index 1) and the local terms fade.
        diffuse *= opacity;
        ambient *= opacity;
        (Color::splat(1.0 - opacity), 1.0)
    } else {
        (Color::ZERO, ior)
    };

    Material {
        name: m.name.clone(),
        color,
        ambient,
        diffuse,
        specular,
        shininess: m.shininess.unwrap_or(d.shininess),
        // MTL's highlight is (N·H)^Ns.
        highlight: Highlight::BlinnPhong,
        reflect,
        transmit,
        ior,
        fresnel,
        emission: extras.ke.unwrap_or(Color::ZERO),
        normal_map: extras.normal_map.clone(),
        bump_map: extras.bump_map.clone(),
        occlusion: None,
        metal_rough: None,
        emission_map: None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn mtl(illum: u8) -> tobj::Material {
        tobj::Material {
            name: "m".into(),
            ambient: Some([0.1, 0.2, 0.3]),
            diffuse: Some([0.6, 0.3, 0.0]),
            specular: Some([0.3, 0.3, 0.6]),
            shininess: Some(50.0),
            optical_density: Some(1.33),
            illumination_model: Some(illum),
            ..Default::default()
        }
    }

    #[test]
    fn illumination_models_switch_terms() {
        let e = Extras::default();
        let m1 = whitted(&mtl(1), &e);
        assert_eq!(
            (m1.specular, m1.reflect, m1.transmit),
            (0.0, 0.0, Color::ZERO)
        );
        assert!((m1.ambient - 0.2).abs() < 1e-6);
        assert_eq!(m1.color, Texture::Solid(Color::new(0.6, 0.3, 0.0)));
        let m2 = whitted(&mtl(2), &e);
        assert!((m2.specular - 0.4).abs() < 1e-6);
        assert_eq!((m2.reflect, m2.highlight), (0.0, Highlight::BlinnPhong));
        let m3 = whitted(&mtl(3), &e);
        assert!((m3.reflect - 0.4).abs() < 1e-6);
        assert_eq!(m3.fresnel, FresnelMode::Off);
        let m5 = whitted(&mtl(5), &e);
        assert_eq!(
            (m5.fresnel, m5.ior, m5.transmit),
            (FresnelMode::Exact, 1.33, Color::ZERO)
        );
        let m6 = whitted(&mtl(6), &e);
        assert!(m6.transmit.abs_diff_eq(Color::splat(0.6), 1e-6));
        assert_eq!((m6.ior, m6.fresnel), (1.33, FresnelMode::Off));
        let m7 = whitted(
            &mtl(7),
            &Extras {
                tf: Some(Color::new(0.5, 0.25, 1.0)),
                ..Extras::default()
            },
        );
        // (1 − Ks)·Tf per channel: the filter keeps its colour.
        assert!(m7.transmit.abs_diff_eq(Color::new(0.3, 0.15, 0.6), 1e-6));
        assert_eq!(m7.fresnel, FresnelMode::Exact);
    }

    #[test]
    fn dissolve_passes_light_straight_through() {
        let mut m = mtl(4);
        m.dissolve = Some(0.25);
        let g = whitted(&m, &Extras::default());
        assert_eq!((g.transmit, g.ior), (Color::splat(0.75), 1.0));
        assert!((g.diffuse - 0.25).abs() < 1e-6);
        assert!((g.reflect - 0.4).abs() < 1e-6);
        // Tr is 1 − d, used when d is absent.
        let mut m = mtl(2);
        m.dissolve = None;
        let t = whitted(
            &m,
            &Extras {
                tr: Some(0.4),
                ..Extras::default()
            },
        );
        assert!(t.transmit.abs_diff_eq(Color::splat(0.4), 1e-6));
    }
}

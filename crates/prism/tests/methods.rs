//! Acceleration methods own their parameters: each declares one table of keys, and the
//! parser, the printer, `--accel`'s help and the documentation all follow it. A toy method
//! declared here (its options, table and build, plus one line in an `accel_methods!` list)
//! parses, prints, reports errors and answers rays like the built-in ones.

use crate::common;

use common::oracle::{random_ray, TestScene};
use common::{icosphere, Rng};
use prism::accel::{
    markdown, Accel, AccelKind, AccelSpec, BruteForce, BruteForceOptions, BvhOptions, Key, Keyed,
    Method,
};
use prism::field_key;
use prism::geometry::Geometry;
use prism::math::{TraceRay, Vec3};
use prism::Stats;

/// The toy: brute force over the primitives in reverse order, optionally skipping all but
/// every `stride`-th one (a deliberately wrong method, to see the oracle catch it).
#[derive(Clone, Debug, PartialEq)]
struct ReversedOptions {
    stride: usize,
    reverse: bool,
}

impl Default for ReversedOptions {
    fn default() -> Self {
        ReversedOptions {
            stride: 1,
            reverse: true,
        }
    }
}

impl Keyed for ReversedOptions {
    const NAME: &'static str = "reversed";
    const SUMMARY: &'static str = "the brute-force list backwards";
    const KEYS: &'static [Key<Self>] = &[
        field_key!("stride" => stride, int 1..=9, "keep every n-th primitive"),
        field_key!("reverse" => reverse, switch, "walk the list backwards"),
    ];
}

impl Method for ReversedOptions {
    fn build(&self, _geometry: &Geometry, prims: Vec<u32>) -> Box<dyn Accel> {
        let mut kept: Vec<u32> = prims.into_iter().step_by(self.stride).collect();
        if self.reverse {
            kept.reverse();
        }
        Box::new(BruteForce::new(kept))
    }
}

/// A method list with the toy added: the one line a new method needs.
mod with_toy {
    use super::ReversedOptions;
    use prism::accel::{BruteForceOptions, BvhOptions};

    prism::accel_methods! {
        BruteForce(BruteForceOptions),
        #[default]
        Bvh(BvhOptions),
        Reversed(ReversedOptions),
    }
}

#[test]
fn a_toy_method_parses_prints_and_explains_its_keys() {
    use with_toy::{AccelKind, AccelSpec};
    assert_eq!(AccelKind::ALL.len(), 3);
    let spec: AccelSpec = "reversed:stride=3".parse().unwrap();
    assert_eq!(
        spec,
        AccelSpec::Reversed(ReversedOptions {
            stride: 3,
            reverse: true
        })
    );
    assert_eq!(spec.to_string(), "reversed:stride=3");
    assert_eq!(
        "reversed:reverse=false"
            .parse::<AccelSpec>()
            .unwrap()
            .to_string(),
        "reversed:reverse=false"
    );
    assert_eq!(
        "reversed".parse::<AccelSpec>().unwrap().to_string(),
        "reversed"
    );
    for (text, phrase) in [
        (
            "reversed:stride=0",
            "bad value '0' for 'stride': expected an integer from 1 to 9",
        ),
        (
            "reversed:stride",
            "'stride' needs a value: expected an integer from 1 to 9",
        ),
        (
            "reversed:leaf=2",
            "unknown parameter 'leaf' for reversed, expected one of: stride, reverse",
        ),
        ("reversed:reverse=maybe", "expected true or false"),
        (
            "octree",
            "unknown accelerator 'octree', expected one of: brute-force, bvh, reversed",
        ),
    ] {
        let err = text.parse::<AccelSpec>().unwrap_err();
        assert!(err.contains(phrase), "{text}: {err}");
    }
    let docs = AccelKind::docs();
    let toy = docs.iter().find(|m| m.name == "reversed").unwrap();
    let keys: Vec<_> = toy
        .keys
        .iter()
        .map(|k| (k.name, k.accepts.as_str(), k.default.as_str()))
        .collect();
    assert_eq!(
        keys,
        [("stride", "1–9", "1"), ("reverse", "switch", "true")]
    );
    assert!(markdown(&docs)
        .contains("`\"reversed\"` (the brute-force list backwards; keys `stride` 1–9"));
}

#[test]
fn a_toy_method_is_held_to_the_oracle() {
    use with_toy::AccelSpec;
    let mut scene = TestScene::new();
    for i in 0..6 {
        let c = Vec3::new(i as f32 * 0.7 - 2.0, 0.1 * i as f32, 0.0);
        scene.add_mesh(icosphere(c, 0.5, 1));
    }
    // The same sphere twice: exact ties, which the tie rule gives to the lower id whatever
    // order the list is walked in.
    scene.add_mesh(icosphere(Vec3::ZERO, 0.5, 1));
    let g = &scene.geometry;
    let prims: Vec<u32> = (0..g.primitives.len() as u32).collect();
    let bounds = prims.iter().fold(prism::math::Aabb::EMPTY, |b, &p| {
        b.union(&g.bounds(p).unwrap())
    });
    let oracle = BruteForce::new(prims.clone());
    let toy = "reversed"
        .parse::<AccelSpec>()
        .unwrap()
        .build(g, prims.clone());
    let broken = "reversed:stride=2"
        .parse::<AccelSpec>()
        .unwrap()
        .build(g, prims);
    let mut rng = Rng::new(7);
    let (mut stats, mut hits, mut broken_differs) = (Stats::default(), 0, false);
    for _ in 0..5000 {
        let ray = TraceRay::new(random_ray(&mut rng, &scene, &bounds));
        let expected = oracle.intersect(g, &ray, f32::INFINITY, &mut stats);
        assert_eq!(toy.intersect(g, &ray, f32::INFINITY, &mut stats), expected);
        assert_eq!(
            toy.occluded(g, &ray, f32::INFINITY, &mut stats),
            expected.is_some()
        );
        hits += expected.is_some() as usize;
        broken_differs |= broken.intersect(g, &ray, f32::INFINITY, &mut stats) != expected;
    }
    assert!(hits > 1000, "only {hits} rays hit");
    assert!(broken_differs, "the oracle comparison cannot fail");
}

#[test]
fn every_key_default_is_accepted_and_prints_as_nothing() {
    for kind in AccelKind::ALL {
        let spec = AccelSpec::from(kind);
        let docs = &AccelSpec::docs()[kind.index()];
        assert_eq!(docs.name, kind.name());
        let params: Vec<String> = docs
            .keys
            .iter()
            .map(|k| format!("{}={}", k.name, k.default))
            .collect();
        let text = format!("{}:{}", kind.name(), params.join(","));
        let text = text.trim_end_matches(':');
        let parsed: AccelSpec = text.parse().unwrap_or_else(|e| panic!("{text}: {e}"));
        assert_eq!(parsed, spec, "{text}");
        assert_eq!(parsed.to_string(), kind.name());
    }
    // The toy's list uses the library's option types unchanged.
    let _ = (BruteForceOptions, BvhOptions::default());
}

/// The key list of `accel` in docs/scene-format.md is the tables' own text.
#[test]
fn scene_format_lists_every_key_as_the_tables_say() {
    let doc = std::fs::read_to_string("../../docs/scene-format.md").unwrap();
    let expected = markdown(&AccelSpec::docs());
    assert!(
        doc.contains(&expected),
        "docs/scene-format.md's `accel` row has drifted from the methods' key tables; it \
         should contain:\n{expected}"
    );
}

/// docs/acceleration.md's method table names each method's keys, in table order.
#[test]
fn acceleration_doc_names_every_key() {
    let doc = std::fs::read_to_string("../../docs/acceleration.md").unwrap();
    for m in AccelSpec::docs() {
        let keys: Vec<String> = m.keys.iter().map(|k| format!("`{}`", k.name)).collect();
        let row = doc
            .lines()
            .find(|l| l.starts_with(&format!("| `{}`", m.name)))
            .unwrap_or_else(|| panic!("docs/acceleration.md has no row for {}", m.name));
        let cells: Vec<&str> = row.split('|').map(str::trim).collect();
        assert_eq!(
            cells[2],
            keys.join(", "),
            "docs/acceleration.md, {}",
            m.name
        );
    }
}

#[test]
fn accel_help_lists_every_key() {
    let help = AccelSpec::help();
    for m in AccelSpec::docs() {
        assert!(
            help.contains(&format!("{}: {}", m.name, m.summary)),
            "{help}"
        );
        for k in &m.keys {
            assert!(help.contains(&format!(
                "{} ({}, default {})",
                k.name, k.accepts, k.default
            )));
        }
    }
    assert!(help.contains("split (0–4, default 0)"));
}

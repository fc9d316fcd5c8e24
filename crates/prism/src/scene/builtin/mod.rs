//! Built-in scenes, reachable as `prism render --builtin NAME` and listed by `prism list`.

mod checkerboard;
mod cornell;
mod cornell_light;
mod mirror_room;
mod pearls;
mod random;
mod shards;
mod slivers;
mod sphereflake;
mod stadium;
mod staging;
mod torusknot;
mod whitted;

use super::Scene;

pub use sphereflake::sphereflake;
pub use torusknot::torusknot;

/// A built-in scene: its name, a one-line description and its constructor.
pub struct Builtin {
    /// The name `--builtin` takes.
    pub name: &'static str,
    /// One line for `prism list`.
    pub description: &'static str,
    build: fn() -> Scene,
}

impl Builtin {
    /// Builds the scene (from scratch each time: built-ins are code, not data).
    pub fn build(&self) -> Scene {
        (self.build)()
    }
}

/// Every built-in scene, in the order `prism list` shows them.
pub const BUILTINS: &[Builtin] = &[
    Builtin {
        name: "whitted",
        description: "homage to Whitted 1980: checkerboard, mirror sphere, hollow glass sphere",
        build: whitted::whitted,
    },
    Builtin {
        name: "cornell",
        description: "Cornell box with a point light, a mirror sphere and a glass sphere",
        build: cornell::cornell,
    },
    Builtin {
        name: "cornell-light",
        description: "the measured Cornell box lit by its ceiling area light (path tracer)",
        build: || cornell_light::cornell_light(cornell_light::Variant::Diffuse),
    },
    Builtin {
        name: "cornell-light-glass",
        description:
            "cornell-light with a mirror sphere and a glass sphere for blocks (path tracer)",
        build: || cornell_light::cornell_light(cornell_light::Variant::Glass),
    },
    Builtin {
        name: "mirror-room",
        description:
            "flat walls and a tilted mirror lit from the eye: polygons only, for --integrator beam",
        build: mirror_room::mirror_room,
    },
    Builtin {
        name: "sphereflake",
        description: "Haines' sphereflake of mirrored spheres, level 4 (7381 spheres)",
        build: || sphereflake(4),
    },
    Builtin {
        name: "checkerboard",
        description: "an endless checkered plane to the horizon: the antialiasing test",
        build: checkerboard::checkerboard,
    },
    Builtin {
        name: "torusknot",
        description: "a bumpy torus knot of one million triangles: the large-mesh benchmark",
        build: || torusknot(1_000_000),
    },
    // The bad cases: one scene that defeats each acceleration method.
    Builtin {
        name: "stadium",
        description: "bad for the grid: a dense knot in a stadium 100× its size crams a few cells",
        build: stadium::stadium,
    },
    Builtin {
        name: "slivers",
        description: "bad for bounding boxes: 10k long thin diagonal triangles, boxes mostly empty",
        build: slivers::slivers,
    },
    Builtin {
        name: "shards",
        description: "bad for the kd-tree: 2k large overlapping triangles, references explode",
        build: shards::shards,
    },
    Builtin {
        name: "pearls",
        description: "bad for the octree: 10k spheres on its centre planes, so it never splits",
        build: pearls::pearls,
    },
];

/// Looks a built-in up by name. `sphereflake:N` selects the sphereflake level N (0–6).
pub fn find(name: &str) -> Option<Scene> {
    if let Some(level) = name.strip_prefix("sphereflake:") {
        let level: u32 = level.parse().ok()?;
        return (level <= 6).then(|| sphereflake(level));
    }
    BUILTINS.iter().find(|b| b.name == name).map(Builtin::build)
}

/// The names of every built-in, in list order.
pub fn names() -> Vec<&'static str> {
    BUILTINS.iter().map(|b| b.name).collect()
}

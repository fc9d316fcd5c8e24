//! `bvh:build=auto`: the builder that should cost a render least, build and trace
//! together, chosen from counts alone (the primitives, whether they are all triangles,
//! the rays the render is expected to trace), so the tree is the same on every machine
//! and run. The model: per candidate the build time per primitive and the trace time per
//! ray relative to binned SAH's tree, times binned's trace time per ray; triangles and
//! other shapes get their own rows (binned SAH builds triangles in packs of four, which
//! makes it cheap there; LBVH's leaves of spheres and cones trace about as fast as binned
//! SAH's). The constants are geometric means over three runs of `prism bench` with every
//! builder (its ten scenes, camera and shadow rays, one thread, process CPU time, builds
//! and traces in turns; 2026-12-07, once LBVH's leaves filled triangle packs,
//! bench/results/bvh-auto-packs{1,2,3}.csv);
//! `bench/bvh-auto-check.py fit RUN.csv...` derives them from such runs and
//! docs/acceleration.md says how. PLOC, SBVH, PHR and sweep are no candidates: in the
//! means they build 1.5–6.5× binned's time and trace no faster.

use crate::accel::bvh::BvhBuilder;

/// One candidate of the model.
struct Candidate {
    builder: BvhBuilder,
    reinsert: bool,
    /// Build time per primitive, ns.
    build_ns: f64,
    /// Trace time per ray relative to binned SAH's tree.
    trace_ratio: f64,
}

/// The model's rows for triangle scenes and for the others, and binned SAH's trace time
/// per ray (camera and shadow rays, ns) for each.
const TRIANGLES: ([Candidate; 3], f64) = (
    [
        row(BvhBuilder::Lbvh, false, 122.0, 1.132),
        row(BvhBuilder::Binned, false, 255.0, 1.0),
        row(BvhBuilder::Binned, true, 329.0, 1.024),
    ],
    143.0,
);
const OTHER_SHAPES: ([Candidate; 3], f64) = (
    [
        row(BvhBuilder::Lbvh, false, 145.0, 1.017),
        row(BvhBuilder::Binned, false, 380.0, 1.0),
        row(BvhBuilder::Binned, true, 562.0, 0.971),
    ],
    86.0,
);

const fn row(builder: BvhBuilder, reinsert: bool, build_ns: f64, trace_ratio: f64) -> Candidate {
    Candidate {
        builder,
        reinsert,
        build_ns,
        trace_ratio,
    }
}

/// What `auto` chose, and why.
pub(crate) struct Choice {
    pub builder: BvhBuilder,
    pub reinsert: bool,
    /// The estimates, as `prism info` and `--stats` show them.
    pub reason: String,
}

/// The candidate with the least estimated build + trace time for `primitives` primitives
/// (`triangles`: all of them triangles) and `rays` rays; the first of equal ones.
pub(crate) fn choose(primitives: usize, triangles: bool, rays: f64) -> Choice {
    let (rows, binned_ns_per_ray) = if triangles { &TRIANGLES } else { &OTHER_SHAPES };
    let rays = rays.max(0.0);
    let total_ms = |c: &Candidate| {
        (primitives as f64 * c.build_ns + rays * binned_ns_per_ray * c.trace_ratio) * 1e-6
    };
    let best = rows
        .iter()
        .reduce(|a, b| if total_ms(b) < total_ms(a) { b } else { a })
        .expect("the model has rows");
    let estimates: Vec<String> = rows
        .iter()
        .map(|c| format!("{} {:.2} ms", name(c), total_ms(c)))
        .collect();
    Choice {
        builder: best.builder,
        reinsert: best.reinsert,
        reason: format!(
            "auto chose {} for {primitives} {} and {rays:.0} expected rays: estimated build + trace {}",
            name(best),
            if triangles { "triangles" } else { "primitives" },
            estimates.join(", ")
        ),
    }
}

/// The candidate as a `bvh:` spec names it.
fn name(c: &Candidate) -> String {
    format!(
        "{}{}",
        c.builder.name(),
        if c.reinsert { ",reinsert" } else { "" }
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn few_rays_get_the_fastest_build_and_many_the_fastest_tree() {
        let preview = choose(1_000_000, true, 0.0);
        assert_eq!(
            (preview.builder, preview.reinsert),
            (BvhBuilder::Lbvh, false)
        );
        let render = choose(1_000_000, true, 1e12);
        let fastest_tree = (TRIANGLES.0.iter())
            .min_by(|a, b| a.trace_ratio.total_cmp(&b.trace_ratio))
            .expect("the model has rows");
        assert_eq!(
            (render.builder, render.reinsert),
            (fastest_tree.builder, fastest_tree.reinsert)
        );
        let told = format!("auto chose {} for 1000000 triangles", name(fastest_tree));
        assert!(render.reason.contains(&told), "{}", render.reason);
        assert!(render.reason.contains("lbvh") && render.reason.contains("binned,reinsert"));
    }

    /// The choice changes where the estimates cross: just below that many rays per
    /// triangle LBVH, just above it binned SAH.
    #[test]
    fn the_choice_turns_where_the_estimates_cross() {
        let [lbvh, binned, _] = &TRIANGLES.0;
        let per_prim = (lbvh.build_ns - binned.build_ns)
            / (TRIANGLES.1 * (binned.trace_ratio - lbvh.trace_ratio));
        let n = 10_000;
        let at = |r: f64| choose(n, true, r * n as f64).builder;
        assert_eq!(at(per_prim * 0.99), BvhBuilder::Lbvh);
        assert_eq!(at(per_prim * 1.01), BvhBuilder::Binned);
    }

    #[test]
    fn nonsense_ray_counts_count_as_none() {
        for rays in [f64::NAN, -5.0] {
            let c = choose(100, false, rays);
            assert_eq!(c.builder, choose(100, false, 0.0).builder);
        }
    }
}

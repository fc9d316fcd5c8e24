//! What `prism bench` found: per scene, one row per method, measured or skipped, and the
//! comparisons the acceleration work asks for (the fastest method for primary rays, each method's
//! speed relative to it).

use prism::accel::AccelSpec;
use prism_lab::bench::{Measured, RaySetSize};

pub(super) enum Outcome {
    Measured(Box<Measured>),
    /// Not run, and why.
    Skipped(String),
}

pub(super) struct Row {
    /// The method as the user wrote it.
    pub method: String,
    pub spec: AccelSpec,
    pub outcome: Outcome,
    /// Whether its hits disagree with the reference accelerator's.
    pub mismatch: bool,
}

impl Row {
    pub(super) fn measured(&self) -> Option<&Measured> {
        match &self.outcome {
            Outcome::Measured(m) => Some(m),
            Outcome::Skipped(_) => None,
        }
    }

    pub(super) fn status(&self) -> String {
        match (&self.outcome, self.mismatch) {
            (Outcome::Skipped(why), _) => format!("skipped: {why}"),
            (Outcome::Measured(_), true) => "hits differ from the reference".into(),
            (Outcome::Measured(_), false) => "ok".into(),
        }
    }

    pub(super) fn is_default(&self) -> bool {
        self.spec == AccelSpec::default()
    }
}

pub(super) struct SceneResult {
    pub name: String,
    /// Primitives in the scene, unbounded ones (planes) included.
    pub primitives: usize,
    pub width: u32,
    pub height: u32,
    pub rays: RaySetSize,
    pub primary_hits: usize,
    pub rows: Vec<Row>,
    /// The shadow methods on the same shadow rays (`--shadows`), if asked for.
    pub shadow_methods: Vec<prism_lab::bench::ShadowMeasured>,
}

impl SceneResult {
    /// The row with the highest primary-ray throughput.
    pub(super) fn fastest(&self) -> Option<usize> {
        self.rows
            .iter()
            .enumerate()
            .filter_map(|(i, r)| r.measured().map(|m| (i, m.primary.mrays_per_s)))
            .max_by(|a, b| a.1.total_cmp(&b.1))
            .map(|(i, _)| i)
    }

    /// Row `i`'s primary-ray throughput over the fastest one's (1 for the fastest).
    pub(super) fn vs_best(&self, i: usize) -> Option<f64> {
        let best = self.rows[self.fastest()?].measured()?.primary.mrays_per_s;
        let own = self.rows[i].measured()?.primary.mrays_per_s;
        (best > 0.0).then(|| own / best)
    }

    /// The default method's row, if it was measured.
    pub(super) fn default_row(&self) -> Option<usize> {
        self.rows
            .iter()
            .position(|r| r.is_default() && r.measured().is_some())
    }
}

/// How close the default must be to the fastest method (docs/acceleration.md): within 10 %.
pub(super) const DEFAULT_TOLERANCE: f64 = 0.9;

/// The closing lines: per scene the fastest method and where the default stands, then
/// how many scenes meet that demand.
pub(super) fn summary(scenes: &[SceneResult]) -> Vec<String> {
    let mut lines = Vec::new();
    let default = AccelSpec::default().to_string();
    let (mut met, mut judged) = (0, 0);
    let mut failing = Vec::new();
    for s in scenes {
        let Some(best) = s.fastest() else {
            continue;
        };
        let mut line = format!(
            "{}: fastest for primary rays is {}",
            s.name, s.rows[best].method
        );
        if let Some(d) = s.default_row() {
            let ratio = s.vs_best(d).unwrap_or(0.0);
            judged += 1;
            if ratio >= DEFAULT_TOLERANCE {
                met += 1;
            } else {
                failing.push(format!("{} ({:.0} %)", s.name, ratio * 100.0));
            }
            line += &format!(
                "; the default ({default}) runs at {:.0} % of it",
                ratio * 100.0
            );
        }
        lines.push(line);
    }
    if judged > 0 {
        let mut line = format!(
            "The default ({default}) is the fastest or within 10 % of it for primary rays on {met} of {judged} scenes"
        );
        if !failing.is_empty() {
            line += &format!("; slower on {}", failing.join(", "));
        }
        lines.push(line + ".");
    }
    lines
}

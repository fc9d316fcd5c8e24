//! The OBJ text checked statement by statement before tobj reads it. tobj reports errors
//! without a position, and takes some input silently in a way the file did not mean: a
//! `usemtl` naming no known material (faces lose their material), NaN coordinates,
//! polylines (`l`) of three points as faces, a leading blank before `usemtl` as part of
//! the name; and it fails on comments after a statement. This pass finds every such
//! problem with file:line:column and rewrites each statement in the plain form tobj reads
//! as meant: one space between words, absolute indices, `v` divided by its w and without
//! vertex colours, `vt` with both coordinates, libraries named by number. Statements prism
//! does not use become blank lines, so line numbers stay those of the file.

use crate::source::LoadError;
use std::fmt::Write;

/// What the scan needs from the material side: `mtllib` lines open libraries (relative to
/// the OBJ file), which define the names that `usemtl` may use.
pub(super) trait Libraries {
    /// Opens the libraries named by the rest of an `mtllib` line, which starts at
    /// `line`:`column`. Returns the number to write after `mtllib` for tobj and the material
    /// names the libraries define.
    fn open(
        &mut self,
        names: &str,
        line: usize,
        column: usize,
    ) -> Result<(usize, Vec<String>), LoadError>;

    /// Whether a library named so far was missing: its materials are then unknown, and a
    /// `usemtl` of a name no library defines means the default material, not an error.
    fn missing(&self) -> bool {
        false
    }
}

/// How many positions, texture coordinates and normals are defined so far. Faces may
/// refer only to those: tobj resolves a group's faces when the group ends, so a reference
/// further ahead would work or fail depending on where the group ends.
#[derive(Default)]
struct Counts {
    positions: usize,
    uvs: usize,
    normals: usize,
}

/// One statement's words with their byte offsets in the line.
pub(super) struct Words<'a> {
    line: &'a str,
    pub words: Vec<(usize, &'a str)>,
}

impl<'a> Words<'a> {
    pub(super) fn new(line: &'a str) -> Self {
        let mut words = Vec::new();
        let mut rest = line;
        let mut offset = 0;
        while let Some(start) = rest.find(|c: char| !c.is_whitespace()) {
            let after = &rest[start..];
            let len = after.find(char::is_whitespace).unwrap_or(after.len());
            words.push((offset + start, &after[..len]));
            offset += start + len;
            rest = &after[len..];
        }
        Words { line, words }
    }

    /// The rest of the line after word `index`, trimmed, with its byte offset.
    pub(super) fn rest_after(&self, index: usize) -> (usize, &'a str) {
        let (at, word) = self.words[index];
        let after = &self.line[at + word.len()..];
        let start = after.len() - after.trim_start().len();
        (at + word.len() + start, after.trim())
    }
}

struct Scanner<'a, 'l> {
    path: &'a str,
    line_number: usize,
    line: &'a str,
    defined: Counts,
    libraries: Option<&'l mut dyn Libraries>,
    known_materials: Vec<String>,
    out: String,
    skipped: std::collections::BTreeSet<&'static str>,
}

/// The OBJ text rewritten for tobj, how many positions (`v`) the file defines, and what
/// it holds that the picture will not show (one phrase each).
pub(super) struct Checked {
    pub text: String,
    pub positions: usize,
    pub skipped: Vec<&'static str>,
}

/// Checks the OBJ `text` (read from `path`) and rewrites it for tobj. Without
/// `libraries`, `mtllib` and `usemtl` statements are dropped: the caller supplies a
/// material of its own.
pub(super) fn check(
    text: &str,
    path: &str,
    libraries: Option<&mut dyn Libraries>,
) -> Result<Checked, LoadError> {
    let mut scanner = Scanner {
        path,
        line_number: 0,
        line: "",
        defined: Counts::default(),
        libraries,
        known_materials: Vec::new(),
        out: String::with_capacity(text.len() + text.len() / 8),
        skipped: std::collections::BTreeSet::new(),
    };
    for (i, raw) in text.split('\n').enumerate() {
        scanner.line_number = i + 1;
        // A comment runs from '#' to the end of the line, also after a statement.
        let line = raw.strip_suffix('\r').unwrap_or(raw);
        scanner.line = line.split('#').next().unwrap_or("");
        scanner.statement()?;
        scanner.out.push('\n');
    }
    Ok(Checked {
        text: scanner.out,
        positions: scanner.defined.positions,
        skipped: scanner.skipped.into_iter().collect(),
    })
}

/// Which numbered element a face corner refers to.
#[derive(Clone, Copy)]
enum Kind {
    Position,
    Uv,
    Normal,
}

impl Kind {
    fn name(self) -> (&'static str, &'static str) {
        match self {
            Kind::Position => ("vertex", "vertices (v)"),
            Kind::Uv => ("texture coordinate", "texture coordinates (vt)"),
            Kind::Normal => ("normal", "normals (vn)"),
        }
    }
}

impl<'a> Scanner<'a, '_> {
    fn error(&self, byte: usize, message: String) -> LoadError {
        let prefix = self.line.get(..byte).unwrap_or(self.line);
        let column = prefix.chars().count() + 1;
        LoadError::Syntax {
            path: self.path.to_string(),
            line: self.line_number,
            column,
            message,
        }
    }

    /// The error for a statement `w` whose count of numbers is not one that `takes` says it
    /// takes, located at its fourth number (at the line's end where it has fewer).
    fn count_error(&self, w: &[(usize, &str)], takes: &str) -> LoadError {
        let at = w.get(4).map_or(self.line.trim_end().len(), |w| w.0);
        self.error(at, format!("{takes}; found {}", w.len() - 1))
    }

    fn statement(&mut self) -> Result<(), LoadError> {
        let words = Words::new(self.line);
        let Some(&(_, keyword)) = words.words.first() else {
            return Ok(());
        };
        let reads = matches!(
            keyword,
            "v" | "vt" | "vn" | "f" | "o" | "g" | "mtllib" | "usemtl"
        );
        if reads && self.line.trim_end().ends_with('\\') {
            return Err(self.error(
                self.line.trim_end().len() - 1,
                "a line continuation ('\\' at the end of a line) is not supported; expected \
                 the statement on one line"
                    .into(),
            ));
        }
        match keyword {
            "v" => self.position(&words),
            "vt" => self.uv(&words),
            "vn" => self.normal(&words),
            "f" => self.face(&words),
            "o" | "g" => {
                let (_, name) = words.rest_after(0);
                let _ = write!(self.out, "{keyword} {name}");
                Ok(())
            }
            "mtllib" => self.mtllib(&words),
            "usemtl" => self.usemtl(&words),
            // What would change the picture and is not drawn: said once per file.
            "cstype" | "curv" | "curv2" | "surf" | "parm" | "trim" | "hole" | "scrv" | "sp"
            | "con" => {
                self.skipped
                    .insert("free-form curves and surfaces (cstype, curv, surf, …)");
                Ok(())
            }
            "s" if !matches!(words.rest_after(0).1, "off" | "0" | "") => {
                self.skipped.insert(
                    "smoothing groups (s): faces without vertex normals (vn) are drawn flat",
                );
                Ok(())
            }
            "usemap" | "maplib" => {
                self.skipped
                    .insert("texture map libraries (maplib, usemap)");
                Ok(())
            }
            // Polylines and points (no area for a ray to hit), smoothing groups switched
            // off, and the rest of the format that does not change the picture: skipped.
            _ => Ok(()),
        }
    }

    fn number(&self, word: (usize, &str), what: &str) -> Result<f32, LoadError> {
        match word.1.parse::<f32>() {
            Ok(v) if v.is_finite() => Ok(v),
            Ok(_) => Err(self.error(
                word.0,
                format!("expected {what} (a finite number), found '{}'", word.1),
            )),
            Err(_) => Err(self.error(
                word.0,
                format!("expected {what} (a number), found '{}'", word.1),
            )),
        }
    }

    fn position(&mut self, words: &Words) -> Result<(), LoadError> {
        let w = &words.words;
        if !matches!(w.len(), 4 | 5 | 7) {
            return Err(self.count_error(
                w,
                "a vertex takes 3 numbers (x y z), 4 (x y z w) or 6 (x y z r g b)",
            ));
        }
        let mut p = [0.0f32; 3];
        for (k, v) in p.iter_mut().enumerate() {
            *v = self.number(w[k + 1], ["x", "y", "z"][k])?;
        }
        match w.len() {
            5 => {
                let weight = self.number(w[4], "the weight w")?;
                if weight == 0.0 {
                    return Err(self.error(w[4].0, "expected a weight w other than 0".into()));
                }
                let q = p.map(|v| v / weight);
                if q.iter().any(|v| !v.is_finite()) {
                    return Err(self.error(
                        w[4].0,
                        format!("dividing by the weight w = {weight} overflows the coordinates"),
                    ));
                }
                let _ = write!(self.out, "v {} {} {}", q[0], q[1], q[2]);
            }
            7 => {
                // Vertex colours: prism has no use for them, but they must be numbers.
                for &word in &w[4..7] {
                    self.number(word, "a vertex colour component")?;
                }
                let _ = write!(self.out, "v {} {} {}", w[1].1, w[2].1, w[3].1);
            }
            _ => {
                let _ = write!(self.out, "v {} {} {}", w[1].1, w[2].1, w[3].1);
            }
        }
        self.defined.positions += 1;
        Ok(())
    }

    fn uv(&mut self, words: &Words) -> Result<(), LoadError> {
        let w = &words.words;
        if !(2..=4).contains(&w.len()) {
            return Err(
                self.count_error(w, "a texture coordinate takes 1 to 3 numbers (u [v [w]])")
            );
        }
        for (k, &word) in w.iter().enumerate().skip(1) {
            self.number(word, ["u", "v", "w"][k - 1])?;
        }
        let v = w.get(2).map_or("0", |w| w.1);
        let _ = write!(self.out, "vt {} {v}", w[1].1);
        self.defined.uvs += 1;
        Ok(())
    }

    fn normal(&mut self, words: &Words) -> Result<(), LoadError> {
        let w = &words.words;
        if w.len() != 4 {
            return Err(self.count_error(w, "a normal takes 3 numbers (x y z)"));
        }
        for k in 1..4 {
            self.number(w[k], ["x", "y", "z"][k - 1])?;
        }
        let _ = write!(self.out, "vn {} {} {}", w[1].1, w[2].1, w[3].1);
        self.defined.normals += 1;
        Ok(())
    }

    fn face(&mut self, words: &Words) -> Result<(), LoadError> {
        let w = &words.words;
        if w.len() < 4 {
            return Err(self.error(
                w[0].0,
                format!("a face needs at least 3 corners; found {}", w.len() - 1),
            ));
        }
        self.out.push('f');
        for &(at, corner) in &w[1..] {
            let parts: Vec<&str> = corner.split('/').collect();
            if parts.len() > 3 || parts[0].is_empty() {
                return Err(self.error(
                    at,
                    format!("expected a face corner v, v/vt, v//vn or v/vt/vn; found '{corner}'"),
                ));
            }
            let mut offset = at;
            let mut resolved = [None; 3];
            for (k, part) in parts.iter().enumerate() {
                if !part.is_empty() {
                    let kind = [Kind::Position, Kind::Uv, Kind::Normal][k];
                    resolved[k] = Some(self.index(part, offset, kind)?);
                }
                offset += part.len() + 1;
            }
            let _ = write!(self.out, " {}", resolved[0].unwrap_or(0));
            match resolved {
                [_, Some(t), Some(n)] => {
                    let _ = write!(self.out, "/{t}/{n}");
                }
                [_, Some(t), None] => {
                    let _ = write!(self.out, "/{t}");
                }
                [_, None, Some(n)] => {
                    let _ = write!(self.out, "//{n}");
                }
                [_, None, None] => {}
            }
        }
        Ok(())
    }

    /// Resolves a 1-based (or negative, relative) index to an absolute 1-based one.
    fn index(&self, text: &str, at: usize, kind: Kind) -> Result<usize, LoadError> {
        let (one, many) = kind.name();
        let defined = match kind {
            Kind::Position => self.defined.positions,
            Kind::Uv => self.defined.uvs,
            Kind::Normal => self.defined.normals,
        };
        let value: i64 = text.parse().map_err(|_| {
            self.error(
                at,
                format!("expected a {one} index (a whole number), found '{text}'"),
            )
        })?;
        let resolved = match value {
            0 => {
                return Err(self.error(
                    at,
                    format!("{one} indices start at 1 (or count back from -1); found 0"),
                ))
            }
            // -1 is the latest one defined above this line.
            v if v < 0 => defined as i64 + v + 1,
            v => v,
        };
        if resolved < 1 {
            return Err(self.error(
                at,
                format!(
                    "relative {one} index {value} reaches before the first one: only {defined} \
                     {many} are defined above it"
                ),
            ));
        }
        if resolved > defined as i64 {
            return Err(self.error(
                at,
                if defined == 0 {
                    format!("the face refers to {one} {value}, but no {many} are defined above it")
                } else {
                    format!(
                        "the face refers to {one} {value}, but only {defined} {many} are defined \
                         above it: expected 1 to {defined} (or -1 to -{defined})"
                    )
                },
            ));
        }
        Ok(resolved as usize)
    }

    fn mtllib(&mut self, words: &Words) -> Result<(), LoadError> {
        let (at, names) = words.rest_after(0);
        let Some(libraries) = self.libraries.as_deref_mut() else {
            return Ok(());
        };
        if names.is_empty() {
            return Err(self.error(at, "expected a material library file name".into()));
        }
        let column = self.line.get(..at).unwrap_or("").chars().count() + 1;
        let (key, defined) = libraries.open(names, self.line_number, column)?;
        self.known_materials.extend(defined);
        let _ = write!(self.out, "mtllib {key}");
        Ok(())
    }

    fn usemtl(&mut self, words: &Words) -> Result<(), LoadError> {
        if self.libraries.is_none() {
            return Ok(());
        }
        let (at, name) = words.rest_after(0);
        if name.is_empty() {
            return Err(self.error(at, "expected a material name after usemtl".into()));
        }
        let missing_library = self.libraries.as_ref().is_some_and(|l| l.missing());
        if !self.known_materials.iter().any(|m| m == name) && !missing_library {
            let message = if self.known_materials.is_empty() {
                format!(
                    "unknown material '{name}': no material library (mtllib) defines materials \
                     above this line"
                )
            } else {
                let mut known: Vec<&str> =
                    self.known_materials.iter().map(String::as_str).collect();
                known.sort_unstable();
                known.dedup();
                let shown = known.len().min(12);
                format!(
                    "unknown material '{name}': expected one of {}{}",
                    known[..shown]
                        .iter()
                        .map(|n| format!("'{n}'"))
                        .collect::<Vec<_>>()
                        .join(", "),
                    if known.len() > shown { ", …" } else { "" }
                )
            };
            return Err(self.error(at, message));
        }
        let _ = write!(self.out, "usemtl {name}");
        Ok(())
    }
}

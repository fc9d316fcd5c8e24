//! MTL material libraries. Each line is checked here with file:line:column errors (tobj
//! gives no positions, and panics on a colour of fewer than three numbers), then tobj reads
//! the plain statements it knows (newmtl, Ka, Kd, Ks, Ns, Ni, d, illum); what it does not
//! read is taken here: `Tf`, `Tr`, `Ke`, the `map_Kd` image with its `-s` scale, the `norm`
//! normal map and the `bump`/`map_Bump` height map with their `-s` and `-bm`. What is read
//! and not rendered (other maps, the options that do not change the picture) is named in
//! one warning per library. `material::whitted` turns the result into prism materials.

use super::material::{whitted, Extras};
use super::scan::Words;
use crate::source::{LoadError, Reader};
use prism::math::{Color, Vec2};
use prism::shading::{BumpMap, ImageTexture, Material, NormalMap};
use std::collections::HashMap;
use std::fmt::Write;
use std::path::{Path, PathBuf};

/// Images already read while loading one OBJ file, so materials sharing one load it once:
/// by file and by whether its values are data (normals, heights) rather than sRGB colours.
pub(super) type TextureCache = HashMap<(PathBuf, bool), ImageTexture>;

/// An image a map statement names, with its options.
struct Map {
    image: ImageTexture,
    /// `-bm`: the bump multiplier (1 without it).
    bm: f32,
}

/// tobj's own reading of a library: its materials and their names' indices.
pub(super) type TobjMaterials = (Vec<tobj::Material>, HashMap<String, usize>);

/// One or more libraries named on one `mtllib` line.
#[derive(Clone, Debug, Default)]
pub(super) struct Library {
    /// Handed back to tobj when it reaches the `mtllib` line.
    pub tobj: TobjMaterials,
    /// prism's materials, in tobj's order.
    pub materials: Vec<Material>,
    /// Statements read but not rendered (see `Scene::warnings`).
    pub warnings: Vec<String>,
}

impl Library {
    /// Appends `other` as tobj merges libraries: later names win.
    pub(super) fn append(&mut self, other: Library) {
        let offset = self.tobj.0.len();
        self.tobj.0.extend(other.tobj.0);
        for (name, index) in other.tobj.1 {
            self.tobj.1.insert(name, index + offset);
        }
        self.materials.extend(other.materials);
        self.warnings.extend(other.warnings);
    }

    pub(super) fn names(&self) -> Vec<String> {
        self.tobj.0.iter().map(|m| m.name.clone()).collect()
    }
}

/// A library's text checked and read: the library, or an error located in it.
pub(super) type Parsed = Result<Library, LoadError>;

/// Reads the library at `path` through `reader`; image files are resolved against its
/// folder. The outer error is the file's (the caller knows where it was named); the inner
/// one is located in the library.
pub(super) fn load(
    path: &Path,
    textures: &mut TextureCache,
    reader: &mut Reader,
) -> Result<Parsed, std::io::Error> {
    let bytes = reader.read_regular_file(path)?;
    Ok(parse(
        &String::from_utf8_lossy(&bytes),
        path,
        textures,
        reader,
    ))
}

/// Checks and reads library text; `path` names it in errors and anchors image files, which
/// are read through `reader`.
pub(super) fn parse(
    text: &str,
    path: &Path,
    textures: &mut TextureCache,
    reader: &mut Reader,
) -> Parsed {
    let mut checker = Checker {
        path,
        dir: path.parent().unwrap_or(Path::new("")),
        line_number: 0,
        line: "",
        extras: Vec::new(),
        textures,
        reader,
        out: String::with_capacity(text.len()),
        warnings: Vec::new(),
        unrendered: std::collections::BTreeSet::new(),
    };
    for (i, raw) in text.split('\n').enumerate() {
        checker.line_number = i + 1;
        let line = raw.strip_suffix('\r').unwrap_or(raw);
        checker.line = line.split('#').next().unwrap_or("");
        checker.statement()?;
        checker.out.push('\n');
    }
    let parsed =
        tobj::load_mtl_buf(&mut checker.out.as_bytes()).map_err(|e| LoadError::Invalid {
            path: path.display().to_string(),
            message: format!("the MTL reader (tobj) failed: {e}"),
        })?;
    if parsed.0.len() != checker.extras.len() {
        return Err(LoadError::Invalid {
            path: path.display().to_string(),
            message: format!(
                "tobj read {} materials where prism counted {} newmtl statements",
                parsed.0.len(),
                checker.extras.len()
            ),
        });
    }
    if !checker.unrendered.is_empty() {
        let names: Vec<&str> = checker.unrendered.iter().map(String::as_str).collect();
        checker.warnings.push(format!(
            "{}: read but not rendered: {} (prism renders map_Kd's colour, norm's normals and \
             bump's or map_Bump's heights, with their -s, and -bm for norm and bump)",
            path.display(),
            names.join(", ")
        ));
    }
    let materials = parsed
        .0
        .iter()
        .zip(&checker.extras)
        .map(|(m, extras)| whitted(m, extras))
        .collect();
    Ok(Library {
        tobj: parsed,
        materials,
        warnings: checker.warnings,
    })
}

struct Checker<'a> {
    path: &'a Path,
    dir: &'a Path,
    line_number: usize,
    line: &'a str,
    extras: Vec<Extras>,
    textures: &'a mut TextureCache,
    /// Reads the image files `map_Kd` names.
    reader: &'a mut Reader,
    out: String,
    warnings: Vec<String>,
    /// Texture statements and options read and not rendered (`map_Ks`, `disp`, `map_Kd
    /// -o`, …), named once in a warning.
    unrendered: std::collections::BTreeSet<String>,
}

impl Checker<'_> {
    fn error(&self, byte: usize, message: String) -> LoadError {
        LoadError::Syntax {
            path: self.path.display().to_string(),
            line: self.line_number,
            column: self.line.get(..byte).unwrap_or(self.line).chars().count() + 1,
            message,
        }
    }

    fn end(&self) -> usize {
        self.line.trim_end().len()
    }

    fn statement(&mut self) -> Result<(), LoadError> {
        let words = Words::new(self.line);
        let Some(&(at, keyword)) = words.words.first() else {
            return Ok(());
        };
        if keyword == "newmtl" {
            let (name_at, name) = words.rest_after(0);
            if name.is_empty() {
                return Err(self.error(name_at, "expected a material name after newmtl".into()));
            }
            let _ = write!(self.out, "newmtl {name}");
            self.extras.push(Extras::default());
            return Ok(());
        }
        let known = matches!(
            keyword,
            "Ka" | "Kd"
                | "Ks"
                | "Ke"
                | "Tf"
                | "Ns"
                | "Ni"
                | "d"
                | "Tr"
                | "illum"
                | "map_Kd"
                | "norm"
                | "bump"
                | "map_Bump"
                | "map_bump"
        );
        if known && self.extras.is_empty() {
            return Err(self.error(
                at,
                format!("'{keyword}' comes before any material: expected newmtl NAME first"),
            ));
        }
        let w = &words.words;
        match keyword {
            "Ka" | "Kd" | "Ks" => {
                let c = self.color(w)?;
                let _ = write!(self.out, "{keyword} {} {} {}", c.x, c.y, c.z);
            }
            "Tf" => {
                let c = self.color(w)?;
                self.current().tf = Some(c);
            }
            "Ke" => {
                let c = self.color(w)?;
                self.current().ke = Some(c);
            }
            "Ns" => {
                let v = self.single(w, "the highlight exponent Ns", 0.0..=f32::MAX)?;
                let _ = write!(self.out, "Ns {v}");
            }
            "Ni" => {
                let v = self.single(
                    w,
                    "the index of refraction Ni",
                    f32::MIN_POSITIVE..=f32::MAX,
                )?;
                let _ = write!(self.out, "Ni {v}");
            }
            "d" => {
                let v = self.single(w, "the dissolve d (opacity)", 0.0..=1.0)?;
                let _ = write!(self.out, "d {v}");
            }
            "Tr" => {
                let v = self.single(w, "the transparency Tr", 0.0..=1.0)?;
                self.current().tr = Some(v);
            }
            "illum" => {
                let (at, text) = *w.get(1).unwrap_or(&(self.end(), ""));
                match text.parse::<u8>() {
                    Ok(v) if v <= 10 && w.len() == 2 => {
                        let _ = write!(self.out, "illum {v}");
                    }
                    _ => {
                        return Err(self.error(
                            at,
                            format!(
                                "expected one illumination model, a whole number from 0 to 10; \
                                 found '{}'",
                                words.rest_after(0).1
                            ),
                        ))
                    }
                }
            }
            "map_Kd" => {
                if let Some(map) = self.texture(&words, false)? {
                    if map.bm != 1.0 {
                        self.unrendered.insert("map_Kd -bm".into());
                    }
                    self.current().texture = Some(map.image);
                }
            }
            // A tangent-space normal map, read as glTF's normalTexture is; -bm scales its
            // x and y as glTF's scale does.
            "norm" => {
                if let Some(map) = self.texture(&words, true)? {
                    self.current().normal_map = Some(NormalMap {
                        texture: map.image,
                        scale: map.bm,
                    });
                }
            }
            // Heights (the MTL specification's bump map), scaled by -bm.
            "bump" | "map_Bump" | "map_bump" => {
                if let Some(map) = self.texture(&words, true)? {
                    self.current().bump_map = Some(BumpMap {
                        texture: grey(&map.image),
                        scale: map.bm,
                    });
                }
            }
            // Other texture maps: said once in a warning, so a model is not drawn
            // differently from how it was authored without a word.
            other if other.starts_with("map_") || matches!(other, "disp" | "decal" | "refl") => {
                self.unrendered.insert(other.to_string());
            }
            // The PBR extension's scalars: read by other renderers, drawn as the Whitted
            // terms above here.
            other @ ("Pr" | "Pm" | "Ps" | "Pc" | "Pcr" | "aniso" | "anisor" | "sharpness") => {
                self.unrendered.insert(other.to_string());
            }
            // Anything else is no MTL statement prism knows of.
            _ => {}
        }
        Ok(())
    }

    fn current(&mut self) -> &mut Extras {
        self.extras.last_mut().expect("checked: newmtl came first")
    }

    fn number(&self, (at, text): (usize, &str), what: &str) -> Result<f32, LoadError> {
        match text.parse::<f32>() {
            Ok(v) if v.is_finite() => Ok(v),
            _ => Err(self.error(
                at,
                format!("expected {what} (a finite number), found '{text}'"),
            )),
        }
    }

    /// `K r g b`, or `K r` for a grey, each component ≥ 0.
    fn color(&self, w: &[(usize, &str)]) -> Result<Color, LoadError> {
        let keyword = w[0].1;
        if let Some(&(at, form @ ("spectral" | "xyz"))) = w.get(1) {
            return Err(self.error(
                at,
                format!("'{keyword} {form}' colours are not supported; expected {keyword} r g b"),
            ));
        }
        if !matches!(w.len(), 2 | 4) {
            let at = w.get(4).map_or(self.end(), |w| w.0);
            return Err(self.error(
                at,
                format!(
                    "expected {keyword} r g b (or one number for a grey); found {} numbers",
                    w.len() - 1
                ),
            ));
        }
        let mut c = [0.0f32; 3];
        for (k, v) in c.iter_mut().enumerate() {
            let word = w[if w.len() == 2 { 1 } else { k + 1 }];
            *v = self.number(word, "a colour component")?;
            if *v < 0.0 {
                return Err(self.error(
                    word.0,
                    format!("expected a colour component ≥ 0, found {}", word.1),
                ));
            }
        }
        Ok(Color::from_array(c))
    }

    fn single(
        &self,
        w: &[(usize, &str)],
        what: &str,
        range: std::ops::RangeInclusive<f32>,
    ) -> Result<f32, LoadError> {
        if w.len() != 2 {
            let at = w.get(2).map_or(self.end(), |w| w.0);
            let found = if w.len() == 1 {
                "nothing".to_string()
            } else {
                format!("{} values", w.len() - 1)
            };
            return Err(self.error(at, format!("expected {what}, one number; found {found}")));
        }
        let v = self.number(w[1], what)?;
        if !range.contains(&v) {
            let bounds = if *range.end() == f32::MAX {
                if *range.start() > 0.0 {
                    "> 0".to_string()
                } else {
                    format!("≥ {}", range.start())
                }
            } else {
                format!("from {} to {}", range.start(), range.end())
            };
            return Err(self.error(w[1].0, format!("expected {what} {bounds}, found {v}")));
        }
        Ok(v)
    }

    /// `map_Kd [options] file` (or `norm`, `bump`, …: the statement's keyword): `-s` kept
    /// as the scale and `-bm` as the multiplier, the other options' arguments skipped and
    /// the options named in the warning of what is not rendered. `data`: the image holds
    /// normals or heights, read without the sRGB curve.
    fn texture(&mut self, words: &Words, data: bool) -> Result<Option<Map>, LoadError> {
        let w = &words.words;
        let keyword = w[0].1;
        let mut scale = Vec2::ONE;
        let mut bm = 1.0;
        let mut i = 1;
        while let Some(&(at, option)) = w.get(i).filter(|(_, t)| t.starts_with('-')) {
            i += 1;
            let (min, max, numeric) = match option {
                "-blendu" | "-blendv" | "-cc" | "-clamp" | "-imfchan" => (1, 1, false),
                "-bm" | "-boost" | "-texres" => (1, 1, true),
                "-mm" => (2, 2, true),
                "-o" | "-s" | "-t" => (1, 3, true),
                _ => {
                    return Err(self.error(
                        at,
                        format!(
                            "unknown {keyword} option '{option}'; expected -blendu, -blendv, \
                             -bm, -boost, -cc, -clamp, -imfchan, -mm, -o, -s, -t or -texres"
                        ),
                    ))
                }
            };
            let mut args = Vec::new();
            while args.len() < max {
                let Some(&word) = w.get(i) else { break };
                if numeric {
                    // -o, -s and -t take one to three numbers: as many as follow.
                    if args.len() >= min && word.1.parse::<f32>().is_err() {
                        break;
                    }
                    args.push(self.number(word, &format!("an argument of {option}"))?);
                } else {
                    args.push(0.0);
                }
                i += 1;
            }
            if args.len() < min {
                return Err(self.error(
                    self.end(),
                    format!("the {keyword} option {option} needs {min} argument(s)"),
                ));
            }
            match option {
                "-s" => {
                    scale = Vec2::new(args[0], args.get(1).copied().unwrap_or(1.0));
                    if scale.min_element() <= 0.0 {
                        return Err(self.error(
                            at,
                            format!(
                                "expected a {keyword} scale -s > 0, found {} {}",
                                scale.x, scale.y
                            ),
                        ));
                    }
                }
                "-bm" => bm = args[0],
                _ => {
                    self.unrendered.insert(format!("{keyword} {option}"));
                }
            }
        }
        let Some(&(file_at, _)) = w.get(i) else {
            return Err(self.error(
                self.end(),
                format!("expected an image file name after {keyword}"),
            ));
        };
        // Files written on Windows name folders with backslashes.
        let name = self.line[file_at..].trim().replace('\\', "/");
        let file = self.dir.join(&name);
        if !file.exists() {
            // As a missing material library: render with the material's colour, and say so.
            self.warnings.push(format!(
                "{}:{}:{}: the {keyword} image {} is missing; the material does without it",
                self.path.display(),
                self.line_number,
                self.line
                    .get(..file_at)
                    .unwrap_or(self.line)
                    .chars()
                    .count()
                    + 1,
                file.display()
            ));
            return Ok(None);
        }
        let key = (file, data);
        let image = match self.textures.get(&key) {
            Some(image) => image.clone(),
            None => {
                let loaded = if data {
                    crate::texture::load_data(&key.0, self.reader)
                } else {
                    crate::texture::load(&key.0, self.reader)
                };
                let image = loaded.map_err(|e| {
                    self.error(
                        file_at,
                        format!("expected a readable PNG or JPEG image for {keyword}: {e}"),
                    )
                })?;
                self.textures.insert(key, image.clone());
                image
            }
        };
        let mut image = image;
        image.scale = scale;
        Ok(Some(Map { image, bm }))
    }
}

/// A height image as one value per texel: the mean of its channels (MTL's default channel
/// for bump maps is the luminance; a grey image has it in every channel).
fn grey(image: &ImageTexture) -> ImageTexture {
    image.map_texels(|c| Color::splat((c.x + c.y + c.z) / 3.0))
}

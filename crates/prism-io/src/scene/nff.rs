//! Eric Haines' Neutral File Format (NFF), the language of the Standard Procedural
//! Databases. Read as a token stream (entities may span lines), with every error naming the
//! file, line and column. docs/nff.md says how each entity maps onto prism's scene.

use super::Scene;
use crate::source::{LoadError, Reader};
use prism::camera::{Camera, Projection};
use prism::geometry::{polygon, Cone, Shape, Sphere, TriangleMesh};
use prism::light::Light;
use prism::math::{Color, Vec3};
use prism::shading::{FresnelMode, Highlight, Material, Texture};
use prism::transfer::Transfer;
use std::collections::HashMap;
use std::path::Path;

/// Reads (through `reader`) and parses an NFF file.
pub fn load(path: &Path, reader: &mut Reader) -> Result<Scene, LoadError> {
    let text = reader
        .read_to_string(path)
        .map_err(|e| LoadError::unreadable(path, e))?;
    parse(&text, &path.display().to_string())
}

struct Token<'a> {
    text: &'a str,
    line: usize,
    column: usize,
}

fn tokenize(text: &str) -> Vec<Token<'_>> {
    let mut tokens = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let line_text = line.split('#').next().unwrap_or("");
        let mut rest = line_text;
        let mut offset = 0;
        while let Some(start) = rest.find(|c: char| !c.is_whitespace()) {
            let after = &rest[start..];
            let len = after.find(char::is_whitespace).unwrap_or(after.len());
            tokens.push(Token {
                text: &after[..len],
                line: i + 1,
                column: offset + start + 1,
            });
            offset += start + len;
            rest = &after[len..];
        }
    }
    tokens
}

/// An `f` line, kept exactly so repeated identical lines share one material.
#[derive(Clone, Copy, PartialEq)]
struct Fill([f32; 8]);

impl Fill {
    fn key(&self) -> [u32; 8] {
        self.0.map(f32::to_bits)
    }

    fn material(&self, name: String) -> Material {
        let [r, g, b, kd, ks, shine, t, ior] = self.0;
        let color = Color::new(r, g, b);
        Material {
            name,
            color: Texture::Solid(color),
            // SPD: "an ambient component should be used for all objects"; its weight is
            // the diffuse one, lit by the scene's ambient light (none by default).
            ambient: kd,
            diffuse: kd,
            // NFF's Ks is both the mirror weight and (as SPD's reader takes it) the
            // highlight weight.
            specular: ks,
            shininess: shine,
            highlight: Highlight::Phong,
            reflect: ks,
            // NFF's T is one number: grey glass.
            transmit: Color::splat(t),
            ior: if t > 0.0 && ior > 0.0 { ior } else { 1.0 },
            fresnel: FresnelMode::Off,
            // NFF has no emission and no texture maps.
            ..Material::default()
        }
    }
}

const DEFAULT_FILL: Fill = Fill([1.0, 1.0, 1.0, 1.0, 0.0, 1.0, 0.0, 1.0]);

#[derive(Default)]
struct MeshBuilder {
    positions: Vec<Vec3>,
    normals: Vec<Vec3>,
    indices: Vec<[u32; 3]>,
}

struct Parser<'a> {
    path: &'a str,
    tokens: Vec<Token<'a>>,
    pos: usize,
    scene: Scene,
    fill: Fill,
    material_ids: HashMap<[u32; 8], u32>,
    /// Polygon meshes by (material, has vertex normals), in first-use order.
    meshes: Vec<((u32, bool), MeshBuilder)>,
    lights: Vec<(Vec3, Option<Color>)>,
    saw_view: bool,
}

/// Parses NFF text (Haines' Neutral File Format, as the SPD scenes write it); `path` names the file
/// in errors.
pub fn parse(text: &str, path: &str) -> Result<Scene, LoadError> {
    let mut p = Parser {
        path,
        tokens: tokenize(text),
        pos: 0,
        scene: Scene {
            background: Color::ZERO,
            ..Scene::default()
        },
        fill: DEFAULT_FILL,
        material_ids: HashMap::new(),
        meshes: Vec::new(),
        lights: Vec::new(),
        saw_view: false,
    };
    while p.pos < p.tokens.len() {
        p.entity()?;
    }
    p.finish()
}

impl<'a> Parser<'a> {
    fn error_at(&self, index: usize, message: String) -> LoadError {
        let (line, column) = match self.tokens.get(index) {
            Some(t) => (t.line, t.column),
            None => self
                .tokens
                .last()
                .map_or((1, 1), |t| (t.line, t.column + t.text.len())),
        };
        LoadError::Syntax {
            path: self.path.to_string(),
            line,
            column,
            message,
        }
    }

    fn next_text(&mut self, what: &str) -> Result<&'a str, LoadError> {
        match self.tokens.get(self.pos) {
            Some(t) => {
                self.pos += 1;
                Ok(t.text)
            }
            None => Err(self.error_at(self.pos, format!("file ends where {what} was expected"))),
        }
    }

    fn number(&mut self, what: &str) -> Result<f32, LoadError> {
        let at = self.pos;
        let text = self.next_text(what)?;
        match text.parse::<f32>() {
            Ok(v) if v.is_finite() => Ok(v),
            Ok(_) => Err(self.error_at(
                at,
                format!("{what} must be a finite number, found '{text}'"),
            )),
            Err(_) => Err(self.error_at(at, format!("expected {what} (a number), found '{text}'"))),
        }
    }

    fn vec3(&mut self, what: &str) -> Result<Vec3, LoadError> {
        Ok(Vec3::new(
            self.number(what)?,
            self.number(what)?,
            self.number(what)?,
        ))
    }

    fn count(&mut self, what: &str, per_item: usize) -> Result<usize, LoadError> {
        let at = self.pos;
        let text = self.next_text(what)?;
        let n: usize = text.parse().map_err(|_| {
            self.error_at(
                at,
                format!("expected {what} (a whole number), found '{text}'"),
            )
        })?;
        if n < 3 {
            return Err(self.error_at(
                at,
                format!("a polygon needs at least 3 vertices, found {n}"),
            ));
        }
        // Refuse counts the rest of the file cannot hold, before allocating for them.
        let available = (self.tokens.len() - self.pos) / per_item;
        if n > available {
            return Err(self.error_at(
                at,
                format!(
                    "polygon announces {n} vertices but the file holds at most {available} more"
                ),
            ));
        }
        Ok(n)
    }

    fn keyword(&mut self, expected: &str) -> Result<(), LoadError> {
        let at = self.pos;
        let text = self.next_text(&format!("'{expected}'"))?;
        if text != expected {
            return Err(self.error_at(
                at,
                format!("expected '{expected}' in the view ('v') block, found '{text}'"),
            ));
        }
        Ok(())
    }

    fn material(&mut self) -> u32 {
        let key = self.fill.key();
        if let Some(&id) = self.material_ids.get(&key) {
            return id;
        }
        let name = format!("f{}", self.scene.materials.len());
        let id = self.scene.add_material(self.fill.material(name));
        self.material_ids.insert(key, id);
        id
    }

    fn mesh(&mut self, smooth: bool) -> &mut MeshBuilder {
        let key = (self.material(), smooth);
        let index = match self.meshes.iter().position(|(k, _)| *k == key) {
            Some(i) => i,
            None => {
                self.meshes.push((key, MeshBuilder::default()));
                self.meshes.len() - 1
            }
        };
        &mut self.meshes[index].1
    }

    fn entity(&mut self) -> Result<(), LoadError> {
        let at = self.pos;
        let keyword = self.next_text("an entity")?;
        match keyword {
            "v" => self.view(at),
            "b" => {
                self.scene.background = self.vec3("a background colour component")?;
                Ok(())
            }
            "l" => {
                let position = self.vec3("a light position coordinate")?;
                // The colour is optional: three more numbers, or the next entity.
                let has_color = self
                    .tokens
                    .get(self.pos)
                    .is_some_and(|t| t.text.parse::<f32>().is_ok());
                let color = if has_color {
                    Some(self.vec3("a light colour component")?)
                } else {
                    None
                };
                self.lights.push((position, color));
                Ok(())
            }
            "f" => {
                let mut f = [0.0; 8];
                let names = [
                    "red",
                    "green",
                    "blue",
                    "Kd",
                    "Ks",
                    "Shine",
                    "T",
                    "index of refraction",
                ];
                for (v, name) in f.iter_mut().zip(names) {
                    *v = self.number(&format!("the fill's {name}"))?;
                }
                self.fill = Fill(f);
                Ok(())
            }
            "s" => {
                let center = self.vec3("a sphere centre coordinate")?;
                let r_at = self.pos;
                let radius = self.number("the sphere radius")?;
                if radius == 0.0 {
                    return Err(self.error_at(r_at, "a sphere radius must not be 0".into()));
                }
                let m = self.material();
                self.scene.geometry.add(
                    Shape::Sphere(Sphere {
                        center,
                        radius: radius.abs(),
                        inside_out: radius < 0.0,
                    }),
                    m,
                );
                Ok(())
            }
            "c" => {
                let base = self.vec3("a cone base coordinate")?;
                let base_r = self.number("the cone base radius")?;
                let apex = self.vec3("a cone apex coordinate")?;
                let apex_r = self.number("the cone apex radius")?;
                // NFF: both radii negative = only the inside is visible. prism's cones are
                // two-sided, so the sign only flips which side counts as outside (unused).
                let cone =
                    Cone::new(base, base_r.abs(), apex, apex_r.abs(), false).ok_or_else(|| {
                        self.error_at(
                            at,
                            "a cone needs distinct base and apex points and radii not both 0"
                                .into(),
                        )
                    })?;
                let m = self.material();
                self.scene.geometry.add(Shape::Cone(Box::new(cone)), m);
                Ok(())
            }
            "p" => self.polygon(false),
            "pp" => self.polygon(true),
            other => Err(self.error_at(
                at,
                format!("unknown NFF entity '{other}'; expected one of v, b, l, f, s, c, p, pp"),
            )),
        }
    }

    fn view(&mut self, at: usize) -> Result<(), LoadError> {
        self.keyword("from")?;
        let eye = self.vec3("a 'from' coordinate")?;
        self.keyword("at")?;
        let look_at = self.vec3("an 'at' coordinate")?;
        self.keyword("up")?;
        let up = self.vec3("an 'up' coordinate")?;
        self.keyword("angle")?;
        let angle = self.number("the view angle in degrees")?;
        self.keyword("hither")?;
        let _hither = self.number("the hither distance")?;
        self.keyword("resolution")?;
        let res_at = self.pos;
        let w = self.number("the horizontal resolution")?;
        let h = self.number("the vertical resolution")?;
        if !(w >= 1.0 && h >= 1.0 && w <= 65536.0 && h <= 65536.0) {
            return Err(self.error_at(
                res_at,
                format!("resolution must be 1 to 65536 pixels, found {w} {h}"),
            ));
        }
        let camera = Camera {
            eye,
            look_at,
            up,
            fov_degrees: angle,
            projection: Projection::Perspective,
        };
        camera
            .validate()
            .map_err(|e| self.error_at(at, format!("invalid view: {e}")))?;
        self.scene.camera = camera;
        self.scene.options.width = w as u32;
        self.scene.options.height = h as u32;
        self.saw_view = true;
        Ok(())
    }

    fn polygon(&mut self, smooth: bool) -> Result<(), LoadError> {
        let at = self.pos - 1;
        let per_vertex = if smooth { 6 } else { 3 };
        let n = self.count("the vertex count", per_vertex)?;
        let mut points = Vec::with_capacity(n);
        let mut normals = Vec::with_capacity(if smooth { n } else { 0 });
        for _ in 0..n {
            points.push(self.vec3("a vertex coordinate")?);
            if smooth {
                let n_at = self.pos;
                let normal = self.vec3("a vertex normal component")?;
                if normal.length_squared() == 0.0 {
                    return Err(self.error_at(n_at, "a vertex normal must not be zero".into()));
                }
                normals.push(normal);
            }
        }
        // Degenerate (zero-area) polygons triangulate to nothing: they are skipped.
        let triangles = polygon::triangulate(&points);
        let _ = at;
        let mesh = self.mesh(smooth);
        let base = mesh.positions.len() as u32;
        mesh.positions.extend(points);
        mesh.normals.extend(normals);
        mesh.indices
            .extend(triangles.into_iter().map(|t| t.map(|i| base + i)));
        Ok(())
    }

    fn finish(mut self) -> Result<Scene, LoadError> {
        if !self.saw_view {
            return Err(LoadError::Invalid {
                path: self.path.to_string(),
                message: "no view ('v') block; NFF files must set the camera".into(),
            });
        }
        // Lights as SPD's own generators set them (lscale in balls.c, gears.c, …): 1/√N
        // each for N lights, for every format that takes an intensity. NFF drops the
        // intensity, and the generators give nearly every surface ka = 0 (balls' floor
        // alone has 0.2), so there is no ambient light: shadows and back faces are dark,
        // as in the SPD's pictures. The ambient term is still evaluated (SPD asks for
        // one, for its cost). Colours are display values (1987): the transfer is
        // `Display`, so the sky b 0.078 0.361 0.753 is written as (20, 92, 192).
        let n = self.lights.len().max(1) as f32;
        let default = Color::splat(1.0 / n.sqrt());
        self.scene.ambient = Color::ZERO;
        self.scene.options.transfer = Transfer::Display;
        self.scene.lights = self
            .lights
            .iter()
            .map(|&(position, color)| Light::Point {
                position,
                color: color.unwrap_or(default),
            })
            .collect();
        for ((material, smooth), m) in std::mem::take(&mut self.meshes) {
            if m.indices.is_empty() {
                continue;
            }
            let normals = smooth.then_some(m.normals);
            let mesh = TriangleMesh::new(m.positions, m.indices, normals, None).map_err(|e| {
                LoadError::Invalid {
                    path: self.path.to_string(),
                    message: e.to_string(),
                }
            })?;
            self.scene.geometry.add_mesh(mesh, material);
        }
        Ok(self.scene)
    }
}

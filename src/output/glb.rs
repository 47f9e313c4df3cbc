//! Binary glTF 2.0 (`.glb`) of a [`Scene`], written with the `gltf` crate's JSON types, and
//! read back (for `vpcut render model.glb`).
//!
//! Layout: one scene with four named nodes, `stock` (triangles, `COLOR_0`), `ideal`
//! (present when meshed; translucent, double-sided), `toolpath` (one `LINE_STRIP` per pass
//! and per rapid, the two told apart by their materials `feed` and `rapid`) and `tool`.
//! Positions are **metres** (glTF's unit): the part's mm times 0.001, `z` along the part
//! axis (glTF viewers show the part lying along their depth axis). Vertex colours are the
//! sRGB colours of the deviation map converted to linear, as glTF requires, stored as
//! normalised 16-bit so that they read back to the same sRGB bytes. No normals are stored:
//! glTF viewers then shade flat, which keeps crests and walls crisp. The scene's `extras`
//! carry the units, the colour legend, the worst finding and the report summary.
//!
//! Pure: bytes in, bytes out.

use crate::output::scene::{Focus, Legend, Mesh, PathKind, Polyline, Scene};
use gltf::json;
use json::validation::Checked::Valid;
use json::validation::USize64;
use std::borrow::Cow;
use std::collections::BTreeMap;

/// glTF positions are metres, the scene's mm.
const M_PER_MM: f32 = 0.001;

/// A `.glb` that cannot be written or read.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum GlbError {
    /// The model exceeds the 4 GiB a binary glTF can hold.
    #[error("the model needs {bytes} bytes, over the 4 GiB a .glb can hold: raise the mesh tolerance (--gltf-tolerance) or coarsen the grid")]
    TooLarge {
        /// Bytes needed.
        bytes: u64,
    },
    /// Not a glTF the reader understands.
    #[error("not a readable glTF binary: {0}")]
    Format(String),
    /// A glTF, but not one vpcut wrote (a node or an attribute it needs is missing).
    #[error("not a vpcut model: {0}")]
    NotVpcut(String),
}

/// sRGB byte to linear light.
fn to_linear(c: u8) -> f64 {
    let s = c as f64 / 255.0;
    if s <= 0.04045 {
        s / 12.92
    } else {
        ((s + 0.055) / 1.055).powf(2.4)
    }
}

/// Linear light to the nearest sRGB byte.
fn to_srgb(l: f64) -> u8 {
    let s = if l <= 0.0031308 {
        l * 12.92
    } else {
        1.055 * l.powf(1.0 / 2.4) - 0.055
    };
    (s * 255.0).round().clamp(0.0, 255.0) as u8
}

/// Builds the JSON and the binary chunk together.
struct Writer {
    root: json::Root,
    bin: Vec<u8>,
    buffer: json::Index<json::Buffer>,
}

impl Writer {
    fn view(
        &mut self,
        bytes: &[u8],
        target: json::buffer::Target,
    ) -> json::Index<json::buffer::View> {
        while self.bin.len() % 4 != 0 {
            self.bin.push(0);
        }
        let offset = self.bin.len();
        self.bin.extend_from_slice(bytes);
        self.root.push(json::buffer::View {
            buffer: self.buffer,
            byte_length: USize64::from(bytes.len()),
            byte_offset: Some(USize64::from(offset)),
            byte_stride: None,
            extensions: None,
            extras: None,
            name: None,
            target: Some(Valid(target)),
        })
    }

    #[allow(clippy::too_many_arguments)]
    fn accessor(
        &mut self,
        bytes: &[u8],
        target: json::buffer::Target,
        count: usize,
        component: json::accessor::ComponentType,
        type_: json::accessor::Type,
        normalized: bool,
        bounds: Option<([f32; 3], [f32; 3])>,
    ) -> json::Index<json::Accessor> {
        let view = self.view(bytes, target);
        self.root.push(json::Accessor {
            buffer_view: Some(view),
            byte_offset: None,
            count: USize64::from(count),
            component_type: Valid(json::accessor::GenericComponentType(component)),
            extensions: None,
            extras: None,
            type_: Valid(type_),
            min: bounds.map(|b| json::Value::from(b.0.to_vec())),
            max: bounds.map(|b| json::Value::from(b.1.to_vec())),
            name: None,
            normalized,
            sparse: None,
        })
    }

    /// Positions in metres, with their exact bounds.
    fn positions(&mut self, pts: &[[f32; 3]]) -> json::Index<json::Accessor> {
        let m: Vec<[f32; 3]> = pts
            .iter()
            .map(|p| [p[0] * M_PER_MM, p[1] * M_PER_MM, p[2] * M_PER_MM])
            .collect();
        let mut lo = [f32::MAX; 3];
        let mut hi = [f32::MIN; 3];
        for p in &m {
            for k in 0..3 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        let bytes: Vec<u8> = m.iter().flatten().flat_map(|v| v.to_le_bytes()).collect();
        self.accessor(
            &bytes,
            json::buffer::Target::ArrayBuffer,
            m.len(),
            json::accessor::ComponentType::F32,
            json::accessor::Type::Vec3,
            false,
            Some((lo, hi)),
        )
    }

    fn material(
        &mut self,
        name: &str,
        rgba: [f32; 4],
        blend: bool,
        metal: f32,
    ) -> json::Index<json::Material> {
        self.root.push(json::Material {
            alpha_mode: Valid(if blend {
                json::material::AlphaMode::Blend
            } else {
                json::material::AlphaMode::Opaque
            }),
            double_sided: blend,
            name: Some(name.to_string()),
            pbr_metallic_roughness: json::material::PbrMetallicRoughness {
                base_color_factor: json::material::PbrBaseColorFactor(rgba),
                metallic_factor: json::material::StrengthFactor(metal),
                roughness_factor: json::material::StrengthFactor(0.6),
                ..Default::default()
            },
            ..Default::default()
        })
    }

    /// A triangle mesh with vertex colours.
    fn mesh(
        &mut self,
        name: &str,
        mesh: &Mesh,
        material: json::Index<json::Material>,
    ) -> Option<json::Index<json::Node>> {
        if mesh.indices.is_empty() {
            return None;
        }
        let positions = self.positions(&mesh.positions);
        // Each sRGB byte's 16-bit linear value, once (a model has millions of vertices).
        let linear: [[u8; 2]; 256] =
            std::array::from_fn(|c| ((to_linear(c as u8) * 65535.0).round() as u16).to_le_bytes());
        let colours: Vec<u8> = mesh
            .colors
            .iter()
            .flat_map(|c| {
                let lin = |k: usize| linear[c[k] as usize];
                [lin(0), lin(1), lin(2), u16::MAX.to_le_bytes()]
            })
            .flatten()
            .collect();
        let colours = self.accessor(
            &colours,
            json::buffer::Target::ArrayBuffer,
            mesh.colors.len(),
            json::accessor::ComponentType::U16,
            json::accessor::Type::Vec4,
            true,
            None,
        );
        let idx: Vec<u8> = mesh.indices.iter().flat_map(|i| i.to_le_bytes()).collect();
        let indices = self.accessor(
            &idx,
            json::buffer::Target::ElementArrayBuffer,
            mesh.indices.len(),
            json::accessor::ComponentType::U32,
            json::accessor::Type::Scalar,
            false,
            None,
        );
        let mut attributes = BTreeMap::new();
        attributes.insert(Valid(json::mesh::Semantic::Positions), positions);
        attributes.insert(Valid(json::mesh::Semantic::Colors(0)), colours);
        let m = self.root.push(json::Mesh {
            extensions: None,
            extras: None,
            name: Some(name.to_string()),
            primitives: vec![json::mesh::Primitive {
                attributes,
                extensions: None,
                extras: None,
                indices: Some(indices),
                material: Some(material),
                mode: Valid(json::mesh::Mode::Triangles),
                targets: None,
            }],
            weights: None,
        });
        Some(self.node(name, m))
    }

    fn node(&mut self, name: &str, mesh: json::Index<json::Mesh>) -> json::Index<json::Node> {
        self.root.push(json::Node {
            mesh: Some(mesh),
            name: Some(name.to_string()),
            ..Default::default()
        })
    }
}

/// Bytes of the model of `scene` (at least: the chunks' sizes are checked before writing).
fn estimate(scene: &Scene) -> u64 {
    let mesh = |m: &Mesh| (m.positions.len() * 20 + m.indices.len() * 4) as u64;
    mesh(&scene.stock)
        + scene.ideal.as_ref().map_or(0, mesh)
        + mesh(&scene.tool)
        + scene
            .toolpath
            .iter()
            .map(|p| p.points.len() as u64 * 12)
            .sum::<u64>()
}

/// The scene as a binary glTF.
pub fn to_glb(scene: &Scene) -> Result<Vec<u8>, GlbError> {
    let limit = u32::MAX as u64 - (1 << 20);
    let bytes = estimate(scene);
    if bytes > limit {
        return Err(GlbError::TooLarge { bytes });
    }
    let mut root = json::Root::default();
    root.asset.generator = Some(format!("vpcut {}", env!("CARGO_PKG_VERSION")));
    let buffer = root.push(json::Buffer {
        byte_length: USize64(0),
        extensions: None,
        extras: None,
        name: None,
        uri: None,
    });
    let mut w = Writer {
        root,
        bin: Vec::with_capacity(bytes as usize),
        buffer,
    };
    let mut nodes = Vec::new();
    let stock_mat = w.material("stock", [1.0, 1.0, 1.0, 1.0], false, 0.0);
    nodes.extend(w.mesh("stock", &scene.stock, stock_mat));
    if let Some(ideal) = &scene.ideal {
        let mat = w.material("ideal", [1.0, 1.0, 1.0, 0.35], true, 0.0);
        nodes.extend(w.mesh("ideal", ideal, mat));
    }
    if !scene.toolpath.is_empty() {
        // The renders' lime green (sRGB 100, 175, 0) in linear light: no deviation colour.
        let feed = w.material("feed", [0.127, 0.429, 0.0, 1.0], false, 0.0);
        let rapid = w.material("rapid", [0.25, 0.25, 0.25, 1.0], false, 0.0);
        let primitives: Vec<json::mesh::Primitive> = scene
            .toolpath
            .iter()
            .filter(|p| p.points.len() >= 2)
            .map(|p| {
                let positions = w.positions(&p.points);
                let mut attributes = BTreeMap::new();
                attributes.insert(Valid(json::mesh::Semantic::Positions), positions);
                json::mesh::Primitive {
                    attributes,
                    extensions: None,
                    extras: None,
                    indices: None,
                    material: Some(match p.kind {
                        PathKind::Feed => feed,
                        PathKind::Rapid => rapid,
                    }),
                    mode: Valid(json::mesh::Mode::LineStrip),
                    targets: None,
                }
            })
            .collect();
        let m = w.root.push(json::Mesh {
            extensions: None,
            extras: None,
            name: Some("toolpath".to_string()),
            primitives,
            weights: None,
        });
        nodes.push(w.node("toolpath", m));
    }
    let tool_mat = w.material("tool", [1.0, 1.0, 1.0, 1.0], false, 0.8);
    nodes.extend(w.mesh("tool", &scene.tool, tool_mat));
    while w.bin.len() % 4 != 0 {
        w.bin.push(0);
    }
    w.root.buffers[0].byte_length = USize64::from(w.bin.len());
    let extras = serde_json::json!({
        "vpcut": {
            "units": "m",
            "scale": "positions are metres: the part's mm x 0.001; z is the part axis",
            "legend": {
                "tolerance_mm": scene.legend.tolerance_mm,
                "scale_mm": scene.legend.scale_mm,
                "colours": "bands of the tolerance as in the plots: within light grey; gouge 1-2x, 2-5x, over 5x light to dark blue; leftover 1-2x, 2-5x, over 5x light orange to dark red; the blank's uncut surface and end faces warm dark grey; cut but not compared light grey; cut by a tool body past its edge purple; the ideal teal",
                "bands_x_tolerance": [1.0, 2.0, 5.0],
            },
            "focus": scene.focus.as_ref().map(|f| serde_json::json!({
                "kind": f.kind, "value_mm": f.value_mm, "point_mm": f.point,
                "turn": f.turn, "flank": f.flank, "angle_deg": f.angle_deg, "z_mm": f.z_mm,
            })),
            "report": serde_json::from_str::<serde_json::Value>(&scene.summary)
                .unwrap_or(serde_json::Value::Null),
        }
    });
    let extras =
        serde_json::value::to_raw_value(&extras).map_err(|e| GlbError::Format(e.to_string()))?;
    let s = w.root.push(json::Scene {
        extensions: None,
        extras: Some(extras),
        name: Some("vpcut".to_string()),
        nodes,
    });
    w.root.scene = Some(s);
    let text = json::serialize::to_string(&w.root).map_err(|e| GlbError::Format(e.to_string()))?;
    let mut json_bytes = text.into_bytes();
    while json_bytes.len() % 4 != 0 {
        json_bytes.push(b' ');
    }
    let total = 12 + 8 + json_bytes.len() + 8 + w.bin.len();
    if total as u64 > u32::MAX as u64 {
        return Err(GlbError::TooLarge {
            bytes: total as u64,
        });
    }
    let glb = gltf::binary::Glb {
        header: gltf::binary::Header {
            magic: *b"glTF",
            version: 2,
            length: total as u32,
        },
        json: Cow::Owned(json_bytes),
        bin: Some(Cow::Owned(w.bin)),
    };
    glb.to_vec().map_err(|e| GlbError::Format(e.to_string()))
}

/// Read a model vpcut wrote back into a scene (positions in mm again).
pub fn from_glb(bytes: &[u8]) -> Result<Scene, GlbError> {
    let g = gltf::Gltf::from_slice(bytes).map_err(|e| GlbError::Format(e.to_string()))?;
    let blob = g.blob.as_deref().unwrap_or(&[]);
    let missing = |what: &str| GlbError::NotVpcut(format!("no {what}"));
    let doc_scene = g
        .default_scene()
        .or_else(|| g.scenes().next())
        .ok_or_else(|| missing("scene"))?;
    let extras: serde_json::Value = doc_scene
        .extras()
        .as_ref()
        .and_then(|r| serde_json::from_str(r.get()).ok())
        .ok_or_else(|| missing("vpcut extras on the scene"))?;
    let v = &extras["vpcut"];
    let legend = Legend {
        tolerance_mm: v["legend"]["tolerance_mm"]
            .as_f64()
            .ok_or_else(|| missing("legend"))?,
        scale_mm: v["legend"]["scale_mm"]
            .as_f64()
            .ok_or_else(|| missing("legend"))?,
    };
    let focus = match &v["focus"] {
        serde_json::Value::Null => None,
        f => {
            let p = &f["point_mm"];
            let c = |k: usize| p[k].as_f64().map(|x| x as f32);
            let point = [
                c(0).ok_or_else(|| missing("focus point"))?,
                c(1).ok_or_else(|| missing("focus point"))?,
                c(2).ok_or_else(|| missing("focus point"))?,
            ];
            // A model from before the place was written: the point's.
            let angle = f64::from(point[1])
                .atan2(f64::from(point[0]))
                .to_degrees()
                .rem_euclid(360.0);
            Some(Focus {
                kind: f["kind"].as_str().unwrap_or("gouge").to_string(),
                value_mm: f["value_mm"].as_f64().unwrap_or(0.0),
                point,
                turn: f["turn"].as_i64().unwrap_or(0),
                flank: f["flank"].as_str().unwrap_or("").to_string(),
                angle_deg: f["angle_deg"].as_f64().unwrap_or(angle),
                z_mm: f["z_mm"].as_f64().unwrap_or(f64::from(point[2])),
            })
        }
    };
    let summary = v["report"].to_string();
    let mut scene = Scene {
        stock: Mesh::default(),
        ideal: None,
        toolpath: Vec::new(),
        tool: Mesh::default(),
        legend,
        focus,
        summary,
    };
    let data = |b: gltf::Buffer<'_>| -> Option<&[u8]> {
        match b.source() {
            gltf::buffer::Source::Bin => Some(blob),
            gltf::buffer::Source::Uri(_) => None,
        }
    };
    let mm = |p: [f32; 3]| [p[0] / M_PER_MM, p[1] / M_PER_MM, p[2] / M_PER_MM];
    for node in doc_scene.nodes() {
        let Some(mesh) = node.mesh() else { continue };
        let name = node.name().unwrap_or("");
        for prim in mesh.primitives() {
            let reader = prim.reader(data);
            let positions: Vec<[f32; 3]> = reader
                .read_positions()
                .ok_or_else(|| missing("positions"))?
                .map(mm)
                .collect();
            match name {
                "toolpath" => {
                    let kind = match prim.material().name() {
                        Some("rapid") => PathKind::Rapid,
                        _ => PathKind::Feed,
                    };
                    scene.toolpath.push(Polyline {
                        kind,
                        points: positions,
                    });
                }
                "stock" | "ideal" | "tool" => {
                    let colors: Vec<[u8; 3]> = match reader.read_colors(0) {
                        Some(c) => c
                            .into_rgba_u16()
                            .map(|c| {
                                let s = |k: usize| to_srgb(c[k] as f64 / 65535.0);
                                [s(0), s(1), s(2)]
                            })
                            .collect(),
                        None => vec![[200, 200, 200]; positions.len()],
                    };
                    let indices: Vec<u32> = match reader.read_indices() {
                        Some(i) => i.into_u32().collect(),
                        None => (0..positions.len() as u32).collect(),
                    };
                    if indices.iter().any(|&i| i as usize >= positions.len()) {
                        return Err(GlbError::Format(format!(
                            "mesh `{name}` has an index out of range"
                        )));
                    }
                    let m = Mesh {
                        positions,
                        colors,
                        indices,
                    };
                    match name {
                        "stock" => scene.stock = m,
                        "ideal" => scene.ideal = Some(m),
                        _ => scene.tool = m,
                    }
                }
                _ => {}
            }
        }
    }
    if scene.stock.indices.is_empty() {
        return Err(missing("`stock` mesh"));
    }
    Ok(scene)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn srgb_round_trips_through_16_bit_linear() {
        for c in 0..=255u8 {
            let l = (to_linear(c) * 65535.0).round() / 65535.0;
            assert_eq!(to_srgb(l), c);
        }
    }
}

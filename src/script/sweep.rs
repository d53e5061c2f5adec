//! Parameter sweeps: the record of each rendered parameter set, and the `sweep.csv` and
//! `sweep.json` tables made from the records.

use glam::DVec3;
use rhai::{Dynamic, Map};
use serde_json::{json, Value};

use crate::trace::RenderStats;

/// A parameter value as the tables write it.
#[derive(Debug, Clone, PartialEq)]
pub enum ParamValue {
    /// An integer.
    Int(i64),
    /// A float.
    Float(f64),
    /// A boolean.
    Bool(bool),
    /// Text (an entity name, …).
    Text(String),
    /// A vector.
    Vec3([f64; 3]),
    /// `()`: adaptive supersampling off, …
    Unit,
}

impl ParamValue {
    /// The table form of a script value.
    pub fn from_dynamic(value: &Dynamic) -> Self {
        if let Ok(i) = value.as_int() {
            ParamValue::Int(i)
        } else if let Ok(f) = value.as_float() {
            ParamValue::Float(f)
        } else if let Ok(b) = value.as_bool() {
            ParamValue::Bool(b)
        } else if value.is_unit() {
            ParamValue::Unit
        } else if let Some(v) = value.clone().try_cast::<DVec3>() {
            ParamValue::Vec3(v.to_array())
        } else {
            ParamValue::Text(value.to_string())
        }
    }

    /// As a CSV field (quoted when it holds a comma or quote).
    pub fn csv(&self) -> String {
        match self {
            ParamValue::Int(i) => i.to_string(),
            ParamValue::Float(f) => f.to_string(),
            ParamValue::Bool(b) => b.to_string(),
            ParamValue::Unit => String::new(),
            ParamValue::Vec3([x, y, z]) => format!("\"({x}, {y}, {z})\""),
            ParamValue::Text(t) if t.contains([',', '"', '\n']) => format!("\"{}\"", t.replace('"', "\"\"")),
            ParamValue::Text(t) => t.clone(),
        }
    }

    /// As JSON.
    pub fn json(&self) -> Value {
        match self {
            ParamValue::Int(i) => json!(i),
            ParamValue::Float(f) => json!(f),
            ParamValue::Bool(b) => json!(b),
            ParamValue::Unit => Value::Null,
            ParamValue::Vec3(v) => json!(v),
            ParamValue::Text(t) => json!(t),
        }
    }

    /// As part of a file name: letters, digits, `.`, `-` only.
    fn slug(&self) -> String {
        let text = match self {
            ParamValue::Unit => "off".to_owned(),
            ParamValue::Vec3([x, y, z]) => format!("{x}_{y}_{z}"),
            other => other.csv(),
        };
        text.chars()
            .map(|c| if c.is_ascii_alphanumeric() || c == '.' || c == '-' { c } else { '_' })
            .collect()
    }
}

/// The parameters of a set, in the map's (alphabetical) key order.
pub fn params_of(map: &Map) -> Vec<(String, ParamValue)> {
    map.iter().map(|(k, v)| (k.to_string(), ParamValue::from_dynamic(v))).collect()
}

/// The file stem of set `index`: `003_aperture-0.1_samples-4` (names capped at 120 bytes).
pub fn file_stem(index: usize, params: &[(String, ParamValue)]) -> String {
    let mut stem = format!("{index:03}");
    for (key, value) in params {
        let part = format!("_{}-{}", ParamValue::Text(key.clone()).slug(), value.slug());
        if stem.len() + part.len() > 120 {
            break;
        }
        stem.push_str(&part);
    }
    stem
}

/// One rendered parameter set.
#[derive(Debug, Clone)]
pub struct SweepRecord {
    /// Position in the sweep.
    pub index: usize,
    /// Image file written.
    pub file: String,
    /// The parameters.
    pub params: Vec<(String, ParamValue)>,
    /// The render's statistics (times, rays by kind).
    pub stats: RenderStats,
    /// Seconds from a fresh World to the written image.
    pub total_seconds: f64,
}

/// Parameter names in order of first appearance across the records.
fn columns(records: &[SweepRecord]) -> Vec<String> {
    let mut names: Vec<String> = Vec::new();
    for (key, _) in records.iter().flat_map(|r| &r.params) {
        if !names.contains(key) {
            names.push(key.clone());
        }
    }
    names
}

/// `sweep.csv`: a row per set with its parameters, times (seconds) and rays by kind.
pub fn csv(records: &[SweepRecord]) -> String {
    let params = columns(records);
    let kinds = RenderStats::default().rays.kinds().map(|(name, _)| format!("rays_{name}"));
    let mut header = vec!["index".to_owned(), "file".to_owned()];
    header.extend(params.iter().cloned());
    header.extend(
        ["script_s", "update_s", "trace_s", "write_s", "total_s", "rays_total", "mrays_per_s"]
            .map(String::from),
    );
    header.extend(kinds);
    let mut out = header.join(",") + "\n";
    for r in records {
        let mut row = vec![r.index.to_string(), ParamValue::Text(r.file.clone()).csv()];
        for name in &params {
            row.push(r.params.iter().find(|(k, _)| k == name).map_or(String::new(), |(_, v)| v.csv()));
        }
        let t = &r.stats.times;
        row.extend(
            [t.script, t.world_update + t.grid_build + t.snapshot, t.trace, t.write, r.total_seconds]
                .map(|s| format!("{s:.6}")),
        );
        row.push(r.stats.rays.total().to_string());
        row.push(format!("{:.3}", r.stats.mrays_per_s()));
        row.extend(r.stats.rays.kinds().map(|(_, n)| n.to_string()));
        out += &(row.join(",") + "\n");
    }
    out
}

/// `sweep.json`: the scene, the script and, per set, its parameters and full statistics.
pub fn json(records: &[SweepRecord], scene: &str, script: &str) -> Value {
    let sets: Vec<Value> = records
        .iter()
        .map(|r| {
            let params: serde_json::Map<String, Value> =
                r.params.iter().map(|(k, v)| (k.clone(), v.json())).collect();
            json!({
                "index": r.index,
                "file": r.file,
                "params": params,
                "total_seconds": r.total_seconds,
                "rays_total": r.stats.rays.total(),
                "mrays_per_s": r.stats.mrays_per_s(),
                "stats": r.stats,
            })
        })
        .collect();
    json!({ "scene": scene, "script": script, "sets": sets })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn record(index: usize, params: Vec<(&str, ParamValue)>) -> SweepRecord {
        let mut stats = RenderStats::default();
        stats.rays.camera = 100 + index as u64;
        stats.rays.lens = 7;
        SweepRecord {
            index,
            file: format!("{index:03}.png"),
            params: params.into_iter().map(|(k, v)| (k.to_owned(), v)).collect(),
            stats,
            total_seconds: 0.5,
        }
    }

    #[test]
    fn csv_has_a_column_per_parameter_and_ray_kind() {
        let records = [
            record(0, vec![("aperture", ParamValue::Float(0.1)), ("samples", ParamValue::Int(4))]),
            record(1, vec![("samples", ParamValue::Int(16)), ("label", ParamValue::Text("a, b".into()))]),
        ];
        let text = csv(&records);
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines.len(), 3);
        assert!(lines[0].starts_with("index,file,aperture,samples,label,script_s,"), "{}", lines[0]);
        assert!(lines[0].ends_with(",rays_camera,rays_lens,rays_shadow,rays_area_shadow,rays_reflection,rays_glossy,rays_refraction,rays_blurry,rays_aov"));
        assert!(lines[1].starts_with("0,000.png,0.1,4,,"), "{}", lines[1]);
        assert!(lines[2].starts_with("1,001.png,,16,\"a, b\","), "{}", lines[2]);
        assert!(lines[2].contains(",108,"), "total rays 101 + 7: {}", lines[2]);
    }

    #[test]
    fn file_stems_name_the_parameters_safely() {
        let params = vec![
            ("aperture".to_owned(), ParamValue::Float(0.05)),
            ("focus_on".to_owned(), ParamValue::Text("red ball/2".into())),
            ("adaptive".to_owned(), ParamValue::Unit),
        ];
        assert_eq!(file_stem(7, &params), "007_aperture-0.05_focus_on-red_ball_2_adaptive-off");
    }
}

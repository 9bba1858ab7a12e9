//! `--set KEY=VALUE`: override any scene field by its path, e.g. `integration.dt_s=0.0005`.
//!
//! The scene is turned into a JSON tree, the value replaced, and the tree read back through the
//! same schema, so an override is checked exactly like the file (unknown field, wrong type).
//! A path may skip an enum variant's name: `cloth.shape.diameter_m` reaches into `Circle`.

use super::scene_file::SceneFile;

/// Applies one `KEY=VALUE` assignment; the error is a human-readable reason.
pub(crate) fn apply(scene: &SceneFile, assignment: &str) -> Result<SceneFile, String> {
    let (key, raw) = assignment
        .split_once('=')
        .ok_or("expected KEY=VALUE, e.g. integration.dt_s=0.0005")?;
    let key = key.trim();
    if key.is_empty() {
        return Err("empty KEY".into());
    }
    let raw = raw.trim();
    let with = |value: serde_json::Value| -> Result<SceneFile, String> {
        let mut tree = serde_json::to_value(scene).map_err(|e| e.to_string())?;
        let mut node = &mut tree;
        let parts: Vec<&str> = key.split('.').collect();
        for (depth, part) in parts.iter().enumerate() {
            node = step_into(node, part)
                .ok_or_else(|| format!("the scene has no field `{}`", parts[..=depth].join(".")))?;
        }
        *node = value;
        serde_json::from_value(tree).map_err(|e| format!("`{key}` does not accept {raw}: {e}"))
    };
    let value = parse_value(raw);
    let as_text = serde_json::Value::String(raw.to_string());
    if value == as_text {
        return with(value);
    }
    // A value that reads as a number, list or struct but does not fit the field may still be
    // meant as text (a name such as `(draft)`); the first error is the one to report.
    with(value).or_else(|e| with(as_text).map_err(|_| e))
}

/// Numbers, booleans, arrays and quoted strings read as JSON; a parenthesised value or a list
/// as RON, the way scene files write them (`(0.0, 0.01, 0.0)`, `(max_speed_m_per_s: 0.002,
/// hold_s: 1.0)`, `[(0.0, 0.5, 0.0), (0.1, 0.5, 0.0)]`); an enum variant with fields as the file
/// writes it (`Dynamic(mass_kg: 0.05, velocity_m_per_s: (0.0, -10.0, 0.0))`, `Circle(diameter_m:
/// 0.3)`); a bare word (a variant such as `Kes`, or a path) as a string.
fn parse_value(raw: &str) -> serde_json::Value {
    let string = || serde_json::Value::String(raw.to_string());
    if let Ok(v) = serde_json::from_str(raw) {
        return v;
    }
    if raw.starts_with('(') || raw.starts_with('[') {
        return parse_ron(raw).unwrap_or_else(string);
    }
    // `Name(fields)`: serde's external tag, {"Name": fields}; one unnamed field is the value.
    if let Some(name) = raw.split_once('(').map(|(name, _)| name)
        && raw.ends_with(')')
        && is_identifier(name.trim())
        && let Some(inner) = parse_ron(&raw[name.len()..])
    {
        let inner = match inner {
            serde_json::Value::Array(mut items) if items.len() == 1 => items.remove(0),
            other => other,
        };
        return serde_json::json!({ name.trim(): inner });
    }
    string()
}

/// A RON value as JSON (struct and variant names dropped), if `raw` is RON.
fn parse_ron(raw: &str) -> Option<serde_json::Value> {
    ron::from_str::<ron::Value>(raw)
        .ok()
        .and_then(|v| serde_json::to_value(v).ok())
}

fn is_identifier(word: &str) -> bool {
    let mut chars = word.chars();
    chars.next().is_some_and(|c| c.is_ascii_alphabetic() || c == '_')
        && chars.all(|c| c.is_ascii_alphanumeric() || c == '_')
}

/// The value of the field at `key` (a `--set` path) as JSON, if the scene has it.
pub(crate) fn read(scene: &SceneFile, key: &str) -> Option<serde_json::Value> {
    let mut tree = serde_json::to_value(scene).ok()?;
    let mut node = &mut tree;
    for part in key.split('.') {
        node = step_into(node, part)?;
    }
    Some(node.clone())
}

/// The child `part` of `node`, looking through a single-variant enum wrapper if needed.
fn step_into<'a>(node: &'a mut serde_json::Value, part: &str) -> Option<&'a mut serde_json::Value> {
    // A list element by its index: `world.colliders.0.friction`.
    if let serde_json::Value::Array(items) = node {
        return part.parse::<usize>().ok().and_then(|i| items.get_mut(i));
    }
    let serde_json::Value::Object(map) = node else {
        return None;
    };
    if map.contains_key(part) {
        return map.get_mut(part);
    }
    // An externally tagged enum: {"Circle": {"diameter_m": ..}}.
    if map.len() == 1 {
        let inner = map.values_mut().next()?;
        if let serde_json::Value::Object(m) = inner {
            return m.get_mut(part);
        }
    }
    None
}

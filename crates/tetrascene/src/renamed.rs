//! Names changed so that each concept has one name across flags, scene keys, Python
//! keywords and records (issue 52; docs/reference/parameters.md). The old names still work
//! for this release, with a warning that names the new one.

/// Flags renamed: (old, new).
pub const RENAMED_FLAGS: [(&str, &str); 3] = [
    ("--epsilon", "--constraint-epsilon"),
    ("--youngs", "--youngs-modulus"),
    ("--poisson", "--poisson-ratio"),
];

/// The warnings for the old flag names among `args`.
pub fn flag_warnings<S: AsRef<str>>(args: &[S]) -> Vec<String> {
    let mut out = Vec::new();
    for arg in args {
        let flag = arg.as_ref().split('=').next().unwrap_or_default();
        if let Some((old, new)) = RENAMED_FLAGS.iter().find(|(old, _)| *old == flag) {
            out.push(format!(
                "warning: {old} is now {new} (the old name works for this release)"
            ));
        }
    }
    out
}

/// The warnings for the old key names in a scene's tables `scene` (TOML parsed), each
/// naming the key where it stands and its new name.
pub fn scene_warnings(scene: &toml::Value) -> Vec<String> {
    let mut out = Vec::new();
    let mut warn = |at: String, old: &str, new: &str| {
        out.push(format!(
            "warning: `{at}.{old}` is now `{at}.{new}` (the old name works for this release)"
        ));
    };
    let table = |v: &toml::Value| v.as_table().cloned().unwrap_or_default();
    let solver = scene.get("solver").map(table).unwrap_or_default();
    if solver.contains_key("epsilon") {
        warn("solver".into(), "epsilon", "constraint_epsilon");
    }
    let output = scene.get("output").map(table).unwrap_or_default();
    for old in ["dir", "surface_dir"] {
        if output.contains_key(old) {
            warn("output".into(), old, "out_dir");
        }
    }
    if output.contains_key("metrics") {
        warn("output".into(), "metrics", "json");
    }
    let list = |key: &str| {
        (scene.get(key).and_then(|v| v.as_array()))
            .cloned()
            .unwrap_or_default()
    };
    for (i, collider) in list("collider").iter().enumerate() {
        let at = format!("collider[{i}]");
        let kind = collider.get("type").and_then(|t| t.as_str());
        if kind == Some("plane") && collider.get("offset").is_some() {
            warn(at.clone(), "offset", "distance");
        }
        if kind == Some("mesh") && collider.get("path").is_some() {
            warn(at.clone(), "path", "mesh");
        }
        keyframe_warnings(collider.get("motion"), &format!("{at}.motion"), &mut warn);
    }
    for (i, object) in list("object").iter().enumerate() {
        let pins = match object.get("pin") {
            Some(toml::Value::Array(pins)) => pins.iter().enumerate().collect::<Vec<_>>(),
            Some(pin) => vec![(usize::MAX, pin)],
            None => Vec::new(),
        };
        for (j, pin) in pins {
            let at = match j {
                usize::MAX => format!("object[{i}].pin.motion"),
                j => format!("object[{i}].pin[{j}].motion"),
            };
            keyframe_warnings(pin.get("motion"), &at, &mut warn);
        }
    }
    out
}

/// The warnings of a motion's keyframes giving `position` (now `translation`).
fn keyframe_warnings(
    motion: Option<&toml::Value>,
    at: &str,
    warn: &mut impl FnMut(String, &str, &str),
) {
    let keyframes = motion
        .and_then(|m| m.get("keyframes"))
        .and_then(|k| k.as_array());
    for (k, keyframe) in keyframes.into_iter().flatten().enumerate() {
        if keyframe.get("position").is_some() {
            warn(format!("{at}.keyframes[{k}]"), "position", "translation");
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn old_names_warn_naming_the_new_ones() {
        let warnings = flag_warnings(&["run", "--youngs=1e5", "--poisson", "0.4", "--dt"]);
        assert_eq!(warnings.len(), 2);
        assert!(warnings[0].contains("--youngs is now --youngs-modulus"));
        let scene: toml::Value = toml::from_str(
            "[solver]\nepsilon = 0.0\n[output]\ndir = \"f\"\n[[collider]]\ntype = \"plane\"\n\
             normal = [0, 1, 0]\noffset = 0.0\nmotion = { keyframes = [{ t = 0.0, \
             position = [0, 1, 0] }] }\n[[object]]\nmesh = \"m\"\n",
        )
        .unwrap();
        let warnings = scene_warnings(&scene);
        assert_eq!(warnings.len(), 4, "{warnings:?}");
        assert!(warnings[3].contains("`collider[0].motion.keyframes[0].translation`"));
        assert!(scene_warnings(&toml::Value::Table(Default::default())).is_empty());
    }
}

//! A scene's tables as JSON and back as TOML: how a scene built in another language (the
//! Python package's `tetrasim.Scene`) reaches the one parser and its checks, and how it
//! becomes a scene file.

use super::*;

/// The tables of the scene text `text` as JSON, once the scene is valid ([`Scene::parse`]:
/// an error names the key that is wrong).
pub fn scene_json(text: &str) -> Result<String> {
    Scene::parse(text)?;
    let value: toml::Value = toml::from_str(text)
        .map_err(|e| Error::param("scene", format!("not TOML: {}", e.message())))?;
    serde_json::to_string(&value).map_err(|e| Error::param("scene", e.to_string()))
}

/// The scene file (TOML) of the tables `json` (as [`scene_json`] gives them), once the
/// scene is valid.
pub fn scene_toml(json: &str) -> Result<String> {
    let value: serde_json::Value =
        serde_json::from_str(json).map_err(|e| Error::param("scene", format!("not JSON: {e}")))?;
    let table = toml::Value::try_from(&value)
        .map_err(|e| Error::param("scene", format!("not a scene's tables: {e}")))?;
    let text = toml::to_string(&table)
        .map_err(|e| Error::param("scene", format!("not a scene's tables: {e}")))?;
    Scene::parse(&text)?;
    Ok(text)
}

//! The CS1230 course scenefile format (see ../shared/CS1230_FORMAT.md).
use super::Scene;
use crate::error::{Error, Result};
use serde_json::Value;
use std::path::Path;

pub fn load(path: &Path, _value: &Value) -> Result<Scene> {
    Err(Error::input(
        path,
        "",
        "CS1230 scenefiles are not supported yet",
    ))
}

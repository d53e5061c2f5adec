//! The scene loader's error type: a file that cannot be read, or a scene that is invalid at
//! a known line, column and field.
//!
//! Every problem in a scene, from a RON syntax error to a material that is not defined, is
//! reported as [`SceneError::Invalid`] and displays as `file:line:col: field `path`: rule`:
//!
//! ```text
//! scenes/bad.ron:12:51: field `objects[0].shape.radius`: must be > 0, got -1
//! ```

use std::path::PathBuf;

/// Why a scene could not be loaded.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    /// The scene file could not be read.
    #[error("{}: cannot read scene: {source}", path.display())]
    Io {
        /// The path as given.
        path: PathBuf,
        /// The underlying I/O error.
        source: std::io::Error,
    },
    /// The scene text is malformed or breaks a rule of the format.
    #[error("{path}:{line}:{col}: field `{field}`: {rule}")]
    Invalid {
        /// Where the text came from: the file path as given, or `<built-in default scene>`.
        path: String,
        /// 1-based line of the offending value.
        line: usize,
        /// 1-based column of the offending value, counted in characters.
        col: usize,
        /// The field, as a path from the scene root such as `objects[2].shape.radius`.
        field: String,
        /// What is wrong and what is allowed, e.g. `must be in [0, 1], got 1.2`.
        rule: String,
    },
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn messages_have_the_documented_shape() {
        let invalid = SceneError::Invalid {
            path: "bad.ron".into(),
            line: 3,
            col: 14,
            field: "materials[1].kd".into(),
            rule: "must be in [0, 1], got 1.2".into(),
        };
        assert_eq!(invalid.to_string(), "bad.ron:3:14: field `materials[1].kd`: must be in [0, 1], got 1.2");
        let io = SceneError::Io {
            path: "missing.ron".into(),
            source: std::io::Error::new(std::io::ErrorKind::NotFound, "not found"),
        };
        assert_eq!(io.to_string(), "missing.ron: cannot read scene: not found");
    }
}

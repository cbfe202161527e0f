//! The description's paths: `${NAME}` variables, `package://` URIs and relative paths.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use crate::kinematics::robot::RobotError;

/// Looks a variable up (the process environment for
/// [`RobotModel::from_description_file`](crate::kinematics::robot::RobotModel::from_description_file)).
pub(super) type Variables<'a> = &'a dyn Fn(&str) -> Option<String>;

/// `text` with every `${NAME}` replaced by the variable's value. `NAME` is ASCII letters,
/// digits and `_`; a `$` not followed by `{` stays as written.
pub(super) fn expand(field: &str, text: &str, vars: Variables<'_>) -> Result<String, RobotError> {
    let invalid = |message: String| RobotError::Description {
        field: field.to_owned(),
        message,
    };
    let mut out = String::with_capacity(text.len());
    let mut rest = text;
    while let Some(start) = rest.find("${") {
        out.push_str(&rest[..start]);
        let after = &rest[start + 2..];
        let end = after
            .find('}')
            .ok_or_else(|| invalid(format!("unterminated \"${{\" in {text:?}")))?;
        let name = &after[..end];
        if name.is_empty() || !name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_') {
            return Err(invalid(format!(
                "\"${{{name}}}\" in {text:?} is not a variable name (letters, digits, _)"
            )));
        }
        let value = vars(name).ok_or_else(|| {
            invalid(format!(
                "environment variable {name} is not set (used in {text:?})"
            ))
        })?;
        out.push_str(&value);
        rest = &after[end + 1..];
    }
    out.push_str(rest);
    Ok(out)
}

/// A path as a file path: expanded, relative to `dir` unless absolute.
pub(super) fn resolve(
    field: &str,
    text: &str,
    dir: &Path,
    vars: Variables<'_>,
) -> Result<PathBuf, RobotError> {
    let expanded = expand(field, text, vars)?;
    if expanded.is_empty() {
        return Err(RobotError::Description {
            field: field.to_owned(),
            message: "empty path".into(),
        });
    }
    Ok(dir.join(expanded))
}

/// A file named by a path or a `package://NAME/rest` URI (through the resolved `packages`).
pub(super) fn resolve_file(
    field: &str,
    text: &str,
    dir: &Path,
    packages: &BTreeMap<String, PathBuf>,
    vars: Variables<'_>,
) -> Result<PathBuf, RobotError> {
    let Some(uri) = text.strip_prefix("package://") else {
        return resolve(field, text, dir, vars);
    };
    let (name, rest) = uri.split_once('/').unwrap_or((uri, ""));
    let root = packages.get(name).ok_or_else(|| RobotError::Description {
        field: field.to_owned(),
        message: format!("package {name:?} of {text:?} is not in [packages]"),
    })?;
    Ok(root.join(expand(field, rest, vars)?))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn vars(name: &str) -> Option<String> {
        (name == "ROOT").then(|| "/opt/robots".to_owned())
    }

    #[test]
    fn variables_expand_and_unknown_ones_are_named() {
        assert_eq!(
            expand("urdf", "${ROOT}/a.urdf", &vars).unwrap(),
            "/opt/robots/a.urdf"
        );
        assert_eq!(expand("urdf", "a$b.urdf", &vars).unwrap(), "a$b.urdf");
        let e = expand("packages.x", "${NOPE}/x", &vars)
            .unwrap_err()
            .to_string();
        assert!(e.contains("packages.x") && e.contains("NOPE"), "{e}");
        let e = expand("urdf", "${ROOT", &vars).unwrap_err().to_string();
        assert!(e.contains("unterminated"), "{e}");
        let e = expand("urdf", "${A B}", &vars).unwrap_err().to_string();
        assert!(e.contains("not a variable name"), "{e}");
    }

    #[test]
    fn files_resolve_through_packages_and_the_directory() {
        let dir = Path::new("/home/me/robot");
        let packages = BTreeMap::from([("desc".to_owned(), PathBuf::from("/opt/desc"))]);
        let file = |t: &str| resolve_file("urdf", t, dir, &packages, &vars);
        assert_eq!(file("r.urdf").unwrap(), Path::new("/home/me/robot/r.urdf"));
        assert_eq!(file("/abs/r.urdf").unwrap(), Path::new("/abs/r.urdf"));
        assert_eq!(
            file("package://desc/urdf/r.urdf").unwrap(),
            Path::new("/opt/desc/urdf/r.urdf")
        );
        let e = file("package://other/r.urdf").unwrap_err().to_string();
        assert!(e.contains("\"other\"") && e.contains("urdf"), "{e}");
        assert!(file("").is_err());
    }
}

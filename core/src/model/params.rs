//! Parameter values checked against their specs: the one check systems (a scene's
//! `params`) and methods (a method's parameters) share.

use crate::InputError;
use crate::model::system::ParamSpec;

/// The values of `specs` (their defaults) overridden by `given` `(name, value, explicit)`, in
/// order: each name must be a spec's and each value finite; an explicit value must lie in
/// its spec's range too (a preset's own values are trusted). Errors name the field
/// `{prefix}{name}` and the parameter's `owner` (`system cvt_pendulum`, `method dla`).
pub fn resolve_params<'a>(
    specs: &[ParamSpec],
    given: impl IntoIterator<Item = (&'a str, f64, bool)>,
    prefix: &str,
    owner: &str,
) -> Result<Vec<f64>, InputError> {
    let mut values: Vec<f64> = specs.iter().map(|p| p.default).collect();
    for (name, value, explicit) in given {
        let field = format!("{prefix}{name}");
        let Some(i) = specs.iter().position(|p| p.name == name) else {
            let valid = specs.iter().map(|p| p.name).collect::<Vec<_>>();
            return Err(InputError::UnknownParam {
                field,
                name: name.into(),
                owner: owner.into(),
                valid: if valid.is_empty() { "none".into() } else { valid.join(", ") },
            });
        };
        let spec = &specs[i];
        if !value.is_finite() {
            return Err(InputError::NonFinite { field, value });
        }
        if explicit && !spec.contains(value) {
            return Err(InputError::ParamOutOfRange {
                field,
                name: name.into(),
                value,
                range: spec.range(),
            });
        }
        values[i] = value;
    }
    Ok(values)
}

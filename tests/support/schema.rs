//! The subset of JSON Schema (2020-12) the schemas in `docs/` use: `type`, `const`, `enum`,
//! `required`, `properties`, `additionalProperties`, `items`, `minItems`, `maxItems`, `minimum`,
//! `maximum` and local `$ref`s. A keyword outside it fails the validation, so a schema cannot
//! silently check less than it says.

use serde_json::Value;

const KNOWN: [&str; 16] = [
    "$schema",
    "$id",
    "title",
    "$defs",
    "$ref",
    "type",
    "const",
    "enum",
    "required",
    "properties",
    "additionalProperties",
    "items",
    "minItems",
    "maxItems",
    "minimum",
    "maximum",
];

/// Every violation of `schema` by `value`, as `path: what`.
pub fn validate(schema: &Value, value: &Value) -> Vec<String> {
    let mut errors = Vec::new();
    check(schema, schema, value, "$", &mut errors);
    errors
}

fn type_matches(name: &str, value: &Value) -> bool {
    match name {
        "object" => value.is_object(),
        "array" => value.is_array(),
        "string" => value.is_string(),
        "number" => value.is_number(),
        "integer" => value.is_u64() || value.is_i64(),
        "boolean" => value.is_boolean(),
        "null" => value.is_null(),
        _ => false,
    }
}

fn check(root: &Value, schema: &Value, value: &Value, path: &str, errors: &mut Vec<String>) {
    let Some(keywords) = schema.as_object() else {
        errors.push(format!("{path}: schema is not an object"));
        return;
    };
    for key in keywords.keys() {
        if !KNOWN.contains(&key.as_str()) {
            errors.push(format!("{path}: unsupported schema keyword {key}"));
        }
    }
    if let Some(reference) = schema["$ref"].as_str() {
        let target = reference.strip_prefix("#/").map(|p| p.split('/').fold(root, |v, k| &v[k]));
        match target {
            Some(target) if !target.is_null() => check(root, target, value, path, errors),
            _ => errors.push(format!("{path}: unresolved $ref {reference}")),
        }
    }
    match &schema["type"] {
        Value::String(t) if !type_matches(t, value) => errors.push(format!("{path}: not {t}: {value}")),
        Value::Array(ts) if !ts.iter().filter_map(Value::as_str).any(|t| type_matches(t, value)) => {
            errors.push(format!("{path}: none of {ts:?}: {value}"))
        }
        _ => {}
    }
    if let Some(expected) = schema.get("const") {
        if expected != value {
            errors.push(format!("{path}: {value} is not {expected}"));
        }
    }
    if let Some(options) = schema["enum"].as_array() {
        if !options.contains(value) {
            errors.push(format!("{path}: {value} not in {options:?}"));
        }
    }
    if let (Some(min), Some(v)) = (schema["minimum"].as_f64(), value.as_f64()) {
        if v < min {
            errors.push(format!("{path}: {v} < {min}"));
        }
    }
    if let (Some(max), Some(v)) = (schema["maximum"].as_f64(), value.as_f64()) {
        if v > max {
            errors.push(format!("{path}: {v} > {max}"));
        }
    }
    if let Some(object) = value.as_object() {
        for key in schema["required"].as_array().into_iter().flatten().filter_map(Value::as_str) {
            if !object.contains_key(key) {
                errors.push(format!("{path}: missing {key}"));
            }
        }
        for (key, item) in object {
            let child = format!("{path}.{key}");
            match schema["properties"].get(key) {
                Some(property) => check(root, property, item, &child, errors),
                None => {
                    if let Some(additional) = schema.get("additionalProperties") {
                        check(root, additional, item, &child, errors);
                    }
                }
            }
        }
    }
    if let Some(items) = value.as_array() {
        if let Some(min) = schema["minItems"].as_u64() {
            if (items.len() as u64) < min {
                errors.push(format!("{path}: fewer than {min} items"));
            }
        }
        if let Some(max) = schema["maxItems"].as_u64() {
            if (items.len() as u64) > max {
                errors.push(format!("{path}: more than {max} items"));
            }
        }
        if let Some(item_schema) = schema.get("items") {
            for (i, item) in items.iter().enumerate() {
                check(root, item_schema, item, &format!("{path}[{i}]"), errors);
            }
        }
    }
}

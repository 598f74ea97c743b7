//! The scene set's bindings (set 0, `SET_SCENE`) for `build.rs`, a module of its own so that
//! `tests/scene_set.rs` can test it too.
//!
//! No list numbers set 0 by hand. Each resource is declared by its owner's header, on one line, as
//! `layout(SCENE(Name), …) … Name …;`: a block whose interface name is `Name`
//! (`readonly buffer Heights { … }`) or an opaque variable named `Name` (`uniform sampler2D
//! blade_alpha;`). `build.rs` finds every such declaration under `shaders/` and `tests/shaders/`,
//! numbers the names (the library's sorted by name from 0, then names only tests declare, so
//! the library's numbers do not depend on the tests), and writes `generated/scene_set.glsl` into
//! `OUT_DIR`, where `SCENE(Name)` becomes `set = SET_SCENE, binding = SCENE_BINDING_Name`. Rust
//! gives each resource by that name (`vk::descriptor::SetLayout::write_named`), never by number.
//!
//! The name is the one the SPIR-V reflects, so a declaration whose name differs from its
//! `SCENE(…)` is refused, and so are two declarations of one name as different kinds of resource
//! (a buffer here, a texel buffer there): each error names the file and line.
//!
//! Specialization constants are numbered the same way (`spec_declarations`, `spec_header`):
//! `layout(constant_id = SPEC(NAME)) const TYPE NAME = …;` takes `SPEC_ID_NAME` of
//! `generated/spec_ids.glsl`, and Rust gives each value by `NAME`.

/// One `layout(SCENE(Name), …)` declaration.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Declaration {
    /// `Name`.
    pub name: String,
    /// What it declares: `buffer`, `uniform` (a uniform block) or the opaque type
    /// (`sampler2D`, `usamplerBuffer`).
    pub kind: String,
    /// `path:line`.
    pub at: String,
    /// Under `shaders/` (the library's), not `tests/shaders/`.
    pub library: bool,
}

/// The `layout(SCENE(Name), …)` declarations of one file (`path` names it in errors and in
/// `Declaration::at`). `//` comments and preprocessor lines are skipped; any other `SCENE(` is
/// an error, so a declaration cannot be missed.
pub fn declarations(path: &str, text: &str, library: bool) -> Result<Vec<Declaration>, String> {
    let mut found = Vec::new();
    for (index, raw) in text.lines().enumerate() {
        let at = format!("{path}:{}", index + 1);
        let line = raw.split("//").next().unwrap_or("").trim();
        if line.starts_with('#') || !contains_word(line, "SCENE") {
            continue;
        }
        let fail = |why: &str| format!("{at}: {why}: `{}`", raw.trim());
        let rest = line.strip_prefix("layout(SCENE(").ok_or_else(|| {
            fail("a scene-set resource is declared `layout(SCENE(Name), …) …`, SCENE first, on one line")
        })?;
        let (name, rest) = rest.split_once(')').ok_or_else(|| fail("SCENE( without `)`"))?;
        let name = name.trim();
        if !is_identifier(name) {
            return Err(fail("SCENE's argument is the resource's GLSL name"));
        }
        let close = layout_end(rest).ok_or_else(|| fail("layout( without its `)`"))?;
        let body = &rest[close + 1..];
        let end = body.find(['{', ';']).ok_or_else(|| fail("the declaration ends at its `{` or `;` on this line"))?;
        let words: Vec<&str> = body[..end].split_whitespace().collect();
        let (kind, declared) = match words.iter().position(|w| *w == "buffer" || *w == "uniform") {
            Some(i) if words[i] == "buffer" && words.len() == i + 2 && body[end..].starts_with('{') => {
                ("buffer".to_owned(), words[i + 1])
            }
            Some(i) if words.len() == i + 2 && body[end..].starts_with('{') => ("uniform".to_owned(), words[i + 1]),
            Some(i) if words[i] == "uniform" && words.len() == i + 3 && body[end..].starts_with(';') => {
                (words[i + 1].to_owned(), words[i + 2])
            }
            _ => return Err(fail("expected `… buffer Name {`, `… uniform Name {` or `uniform TYPE Name;`")),
        };
        if declared != name {
            return Err(fail(&format!("SCENE({name}) declares `{declared}`: a resource is named as it is declared")));
        }
        found.push(Declaration { name: name.to_owned(), kind, at, library });
    }
    Ok(found)
}

/// Each name and its binding: the library's names sorted from 0, then the tests' own. Two
/// declarations of one name as different kinds are an error naming both.
pub fn numbers(declarations: &[Declaration]) -> Result<Vec<(String, u32, &Declaration)>, String> {
    let mut first: std::collections::BTreeMap<(bool, &str), &Declaration> = std::collections::BTreeMap::new();
    for d in declarations {
        if let Some(other) = declarations.iter().find(|o| o.name == d.name && o.kind != d.kind) {
            return Err(format!(
                "{}: scene-set resource `{}` is a {} here and a {} at {}: one name is one resource",
                d.at, d.name, d.kind, other.kind, other.at
            ));
        }
        let library = declarations.iter().any(|o| o.name == d.name && o.library);
        // Library names first (`!library` sorts `false` first), by name.
        first.entry((!library, d.name.as_str())).or_insert(d);
    }
    Ok(first.into_iter().enumerate().map(|(i, ((_, name), d))| (name.to_owned(), i as u32, d)).collect())
}

/// `generated/scene_set.glsl`: the `SCENE` macro and one `SCENE_BINDING_Name` per name.
pub fn header(declarations: &[Declaration]) -> Result<String, String> {
    let mut out = String::from(
        "// Generated by build.rs (build/scene_set.rs) from the `layout(SCENE(Name), …)` declarations of\n\
         // shaders/ and tests/shaders/: set 0's bindings, numbered by name. Edit the declarations instead.\n\
         #ifndef MEADOW_SCENE_SET_GLSL\n#define MEADOW_SCENE_SET_GLSL\n#include \"common/shared.glsl\"\n\n\
         // The layout qualifier of scene-set resource `name`.\n\
         #define SCENE(name) set = SET_SCENE, binding = SCENE_BINDING_##name\n\n",
    );
    for (name, binding, d) in numbers(declarations)? {
        out.push_str(&format!("#define SCENE_BINDING_{name} {binding} // {}, {}\n", d.kind, d.at));
    }
    out.push_str("\n#endif\n");
    Ok(out)
}

/// Whether `line` holds `word` as a whole identifier.
fn contains_word(line: &str, word: &str) -> bool {
    line.match_indices(word).any(|(i, _)| {
        let ident = |c: char| c.is_ascii_alphanumeric() || c == '_';
        !line[..i].ends_with(ident) && !line[i + word.len()..].starts_with(ident)
    })
}

fn is_identifier(name: &str) -> bool {
    name.starts_with(|c: char| c.is_ascii_alphabetic() || c == '_')
        && name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_')
}

/// The index in `rest` (what follows `SCENE(Name)`) of the `)` closing the `layout(`.
fn layout_end(rest: &str) -> Option<usize> {
    let mut depth = 0;
    for (i, c) in rest.char_indices() {
        match c {
            '(' => depth += 1,
            ')' if depth == 0 => return Some(i),
            ')' => depth -= 1,
            _ => {}
        }
    }
    None
}

/// The `layout(constant_id = SPEC(NAME)) const TYPE NAME = …;` declarations of one file:
/// specialization constants are numbered like set 0 (`spec_header`), and pipelines fill them by
/// name (`vk::pipeline::specialization`). Other uses of `SPEC(NAME)` (`local_size_x_id =
/// SPEC(CULL_GROUP)`) are not declarations.
pub fn spec_declarations(path: &str, text: &str, library: bool) -> Result<Vec<Declaration>, String> {
    let mut found = Vec::new();
    for (index, raw) in text.lines().enumerate() {
        let line = raw.split("//").next().unwrap_or("").trim();
        // A constant of one shader alone may keep an id of its own (overlay.frag's): no other
        // shader shares its ids, and Rust gives it by name all the same.
        let Some(rest) = line.strip_prefix("layout(constant_id = SPEC(") else { continue };
        let fail = |why: &str| format!("{path}:{}: {why}: `{}`", index + 1, raw.trim());
        let (name, rest) = rest.split_once(')').ok_or_else(|| fail("SPEC( without `)`"))?;
        let words: Vec<&str> = rest.strip_prefix(')').unwrap_or("").split_whitespace().collect();
        match words.as_slice() {
            ["const", kind, declared, "=", ..] if *declared == name && is_identifier(name) => found.push(Declaration {
                name: name.to_owned(),
                kind: (*kind).to_owned(),
                at: format!("{path}:{}", index + 1),
                library,
            }),
            _ => return Err(fail(&format!("expected `layout(constant_id = SPEC({name})) const TYPE {name} = …;`"))),
        }
    }
    Ok(found)
}

/// `generated/spec_ids.glsl`: the `SPEC` macro and one `SPEC_ID_NAME` per constant.
pub fn spec_header(declarations: &[Declaration]) -> Result<String, String> {
    let mut out = String::from(
        "// Generated by build.rs (build/scene_set.rs) from the `layout(constant_id = SPEC(NAME))`\n\
         // declarations of shaders/ and tests/shaders/: specialization-constant ids, numbered by name.\n\
         #ifndef MEADOW_SPEC_IDS_GLSL\n#define MEADOW_SPEC_IDS_GLSL\n\n\
         // The id of specialization constant `name`.\n#define SPEC(name) SPEC_ID_##name\n\n",
    );
    for (name, id, d) in numbers(declarations)? {
        out.push_str(&format!("#define SPEC_ID_{name} {id} // {}, {}\n", d.kind, d.at));
    }
    out.push_str("\n#endif\n");
    Ok(out)
}

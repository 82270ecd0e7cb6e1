//! What a person reads when a file does not read: the parser's message in the user's words,
//! not Rust's (`expected f64` -> `expected a number`), and, for a file given to the wrong
//! command, what kind of file it looks like and what to do with it (a joint spec given to
//! `penedge detect`: run `penedge generate` first).

/// The serde parser's message in plain words: value types by what a person writes (a
/// number, a whole number, text, a list, a table), Rust type names left out.
pub(crate) fn plain(message: &str) -> String {
    let mut out = too_large(message).unwrap_or_else(|| message.to_string());
    // The value found (`invalid type: integer `1``) and its kind.
    for (rust, plain) in [
        ("invalid type: floating point `", "got the number `"),
        ("invalid type: integer `", "got the whole number `"),
        ("invalid value: integer `", "got the whole number `"),
        ("invalid value: floating point `", "got the number `"),
        ("invalid type: string ", "got the text "),
        ("invalid type: boolean `", "got `"),
        ("invalid type: sequence", "got a list"),
        ("invalid type: map", "got a table"),
        ("invalid type: null", "got null"),
        ("invalid type: unit value", "got null"),
        ("invalid type: option", "got a value"),
        ("unknown variant", "unknown kind"),
    ] {
        out = out.replace(rust, plain);
    }
    // What was expected.
    for (rust, plain) in [
        ("expected f64", "expected a number"),
        ("expected f32", "expected a number"),
        ("expected u64", "expected a whole number, 0 or more"),
        (
            "expected u32",
            "expected a whole number from 0 to 4294967295",
        ),
        ("expected usize", "expected a whole number, 0 or more"),
        ("expected i64", "expected a whole number"),
        ("expected i32", "expected a whole number"),
        ("expected a string", "expected text (in quotes)"),
        ("expected a sequence", "expected a list [...]"),
        ("expected a map", "expected a table of fields"),
        ("expected a boolean", "expected true or false"),
        ("EOF while parsing", "the file ends in the middle of"),
        ("trailing characters", "more text after the end of the data"),
        ("expected value", "not valid JSON here (expected a value)"),
    ] {
        out = out.replace(rust, plain);
    }
    out = replace_words(&out, "expected struct ", "expected a table of fields");
    out = replace_words(
        &out,
        "expected internally tagged enum ",
        "expected a table of fields",
    );
    out = replace_length(&out, "invalid length ", "got a list of ", " values");
    out = replace_length(&out, "an array of length ", "a list of ", " values");
    out = replace_length(&out, "a tuple of size ", "a list of ", " values");
    if let Some(rest) = out.strip_prefix("missing field `") {
        if let Some((name, tail)) = rest.split_once('`') {
            out = format!("the field `{name}` is missing{tail}");
        }
    }
    if let Some(rest) = out.strip_prefix("unknown field `") {
        if let Some((name, tail)) = rest.split_once("`, expected ") {
            let (known, after) = split_known(tail);
            out = format!("unknown field `{name}` (a typo?); the fields here are {known}{after}");
        }
    }
    out
}

/// A whole number above the largest of its type (`9223372036854775808`, expected `i64`),
/// said so: `got the whole number `N`, which is too large: expected a whole number up to M`
/// (it read "got the whole number `N`, expected a whole number").
fn too_large(message: &str) -> Option<String> {
    let start = message.find("integer `")? + "integer `".len();
    let (digits, rest) = message[start..].split_once('`')?;
    let value: i128 = digits.parse().ok()?;
    let rest = rest.strip_prefix(", expected ")?;
    let end = rest
        .find(|c: char| !c.is_ascii_alphanumeric())
        .unwrap_or(rest.len());
    let largest: i128 = match &rest[..end] {
        "i64" => i64::MAX as i128,
        "i32" => i32::MAX as i128,
        "u32" => u32::MAX as i128,
        "u64" | "usize" => u64::MAX as i128,
        _ => return None,
    };
    (value > largest).then(|| {
        format!(
            "got the whole number `{digits}`, which is too large: expected a whole number up \
             to {largest}{}",
            &rest[end..]
        )
    })
}

/// `expected one of `a`, `b`` or `expected `a`` up to the message's position suffix.
fn split_known(tail: &str) -> (&str, &str) {
    let known = tail.strip_prefix("one of ").unwrap_or(tail);
    match known.find(" at line ") {
        Some(i) => (&known[..i], &known[i..]),
        None => (known, ""),
    }
}

/// `text` with `word` and the identifier after it replaced by `plain`.
fn replace_words(text: &str, word: &str, plain: &str) -> String {
    let Some(start) = text.find(word) else {
        return text.to_string();
    };
    let rest = &text[start + word.len()..];
    let end = rest
        .find(|c: char| !(c.is_alphanumeric() || c == '_'))
        .unwrap_or(rest.len());
    format!("{}{plain}{}", &text[..start], &rest[end..])
}

/// `text` with `word N` replaced by `before N after`.
fn replace_length(text: &str, word: &str, before: &str, after: &str) -> String {
    let Some(start) = text.find(word) else {
        return text.to_string();
    };
    let rest = &text[start + word.len()..];
    let end = rest
        .find(|c: char| !c.is_ascii_digit())
        .unwrap_or(rest.len());
    if end == 0 {
        return text.to_string();
    }
    format!(
        "{}{before}{}{after}{}",
        &text[..start],
        &rest[..end],
        &rest[end..]
    )
}

/// What kind of file `text` looks like, when it is not a block file: a sentence saying
/// what it is and what to do with it, or `None` when it looks like a (broken) block file.
pub(crate) fn not_a_block_file(text: &str) -> Option<String> {
    let start = text.trim_start_matches('\u{feff}').trim_start();
    match start.chars().next() {
        None => {
            return Some("the file is empty; a block file is written by `penedge generate`".into())
        }
        Some('{') => {}
        Some('[') if looks_like_toml(start) => return Some(toml_spec()),
        Some('[') => {
            return Some(format!(
                "this is a JSON list, not a block file: a block file is one JSON object, \
                 {BLOCK_FILE_SHAPE}"
            ))
        }
        Some('<') => {
            return Some(
                "this looks like an XML file (a ParaView .vtu or .vtp file?), not a block \
                 file: give `penedge detect` the .json file that `penedge generate -o` writes"
                    .into(),
            )
        }
        Some(_) if looks_like_toml(start) => return Some(toml_spec()),
        Some(_) => {
            return Some(format!(
                "this is not a block file (JSON): a block file is one JSON object, \
                 {BLOCK_FILE_SHAPE}"
            ))
        }
    }
    let value: serde_json::Value = serde_json::from_str(text).ok()?;
    let object = value.as_object()?;
    match object.get("format").and_then(|f| f.as_str()) {
        Some(super::json::FORMAT) => None,
        Some(other) => Some(format!(
            "its format is `{other}`, not `{}`: not a penedge block file",
            super::json::FORMAT
        )),
        None if object.contains_key("domain") && object.contains_key("joints") => Some(
            "this looks like a joint spec (JSON), not a block file: run `penedge generate` on \
             it first, then give the block file it writes (-o blocks.json) to this command"
                .into(),
        ),
        None => Some(format!(
            "no `format` field: not a penedge block file, {BLOCK_FILE_SHAPE}"
        )),
    }
}

/// What a block file looks like, for the messages above.
const BLOCK_FILE_SHAPE: &str = "{\"format\": \"penedge-blocks\", \"version\": 1, \"blocks\": \
     [{\"vertices\": [[x, y, z], ...], \"faces\": [[0, 1, 2], ...]}, ...]} (see \
     docs/block-file-format.md; `penedge generate -o blocks.json` writes one)";

fn toml_spec() -> String {
    "this looks like a joint spec (TOML), not a block file: run `penedge generate` on it \
     first, then give the block file it writes (-o blocks.json) to this command"
        .into()
}

/// Whether the text looks like TOML: a `[table]` header or a `key = value` line first.
fn looks_like_toml(text: &str) -> bool {
    let first = text
        .lines()
        .map(str::trim)
        .find(|l| !l.is_empty() && !l.starts_with('#'));
    first.is_some_and(|line| {
        let header = line.starts_with('[')
            && line.ends_with(']')
            && line
                .trim_matches(|c| c == '[' || c == ']')
                .chars()
                .all(|c| c.is_alphanumeric() || "_-. \"".contains(c))
            && line.chars().any(char::is_alphabetic);
        let key_value = line.split_once('=').is_some_and(|(key, _)| {
            let key = key.trim();
            !key.is_empty()
                && key
                    .chars()
                    .all(|c| c.is_alphanumeric() || "_-.\"".contains(c))
        });
        header || key_value
    })
}

/// A spec file that holds a block file: what to do with it instead (or `None`).
pub(crate) fn not_a_spec(text: &str) -> Option<String> {
    let value: serde_json::Value = serde_json::from_str(text).ok()?;
    let format = value.as_object()?.get("format")?.as_str()?;
    (format == super::json::FORMAT).then(|| {
        "this is a block file (written by `penedge generate`), not a joint spec: give it to \
         `penedge detect` or `penedge show`"
            .into()
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rust_type_names_become_plain_words() {
        let cases = [
            (
                "invalid type: string \"a\", expected f64 at line 1 column 5",
                "got the text \"a\", expected a number at line 1 column 5",
            ),
            (
                "invalid type: integer `1`, expected a string",
                "got the whole number `1`, expected text (in quotes)",
            ),
            (
                "invalid length 2, expected an array of length 3",
                "got a list of 2 values, expected a list of 3 values",
            ),
            (
                "invalid type: map, expected a sequence",
                "got a table, expected a list [...]",
            ),
            (
                "invalid type: sequence, expected struct SystemFile",
                "got a list, expected a table of fields",
            ),
            ("missing field `faces`", "the field `faces` is missing"),
            (
                "unknown field `dipp`, expected one of `dip`, `spacing` at line 3 column 1",
                "unknown field `dipp` (a typo?); the fields here are `dip`, `spacing` at line 3 \
                 column 1",
            ),
            (
                "invalid value: integer `9223372036854775808`, expected i64 at line 1 column 9",
                "got the whole number `9223372036854775808`, which is too large: expected a \
                 whole number up to 9223372036854775807 at line 1 column 9",
            ),
            (
                "invalid value: integer `-1`, expected u32",
                "got the whole number `-1`, expected a whole number from 0 to 4294967295",
            ),
        ];
        for (rust, plain_words) in cases {
            assert_eq!(plain(rust), plain_words);
        }
    }

    #[test]
    fn the_kind_of_a_file_that_is_not_a_block_file() {
        let kind = |text: &str| not_a_block_file(text).unwrap_or_default();
        assert!(kind("[domain]\ntype = \"box\"\n").contains("joint spec (TOML)"));
        assert!(kind("# rock\n\n[[joints]]\ntype = \"set\"").contains("joint spec (TOML)"));
        assert!(kind("title = \"x\"").contains("joint spec (TOML)"));
        assert!(kind("[1, 2, 3]").contains("JSON list"));
        assert!(kind("<?xml version=\"1.0\"?>").contains("XML"));
        assert!(kind("{\"domain\": {}, \"joints\": []}").contains("joint spec (JSON)"));
        assert!(kind("{\"format\": \"other\"}").contains("`other`"));
        assert!(kind("block_a,block_b\n0,1\n").contains("not a block file"));
        assert!(kind("").contains("empty"));
        assert_eq!(not_a_block_file("{\"format\": \"penedge-blocks\"}"), None);
        assert_eq!(not_a_block_file("{\"format\": \"penedge-blocks\", "), None);
    }
}

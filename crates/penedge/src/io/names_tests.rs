//! The names of a spec's entries and the unit's name, in a spec and in a block file: a name
//! with `|` (the separator of the contact table's `set_a`, `set_b`), a name given twice and
//! a unit's name that is not a short label are errors naming the entry.

use super::json::{from_json_str, to_json_string};
use super::spec::parse_toml;
use super::IoError;
use crate::generation::{generate, GenerationError, MAX_UNIT_CHARS};

/// A 10 m box cut by two horizontal planes, named `names` (`None`: no name).
fn spec(names: [Option<&str>; 2]) -> String {
    let mut text = "[domain]\ntype = \"box\"\nmin = [0, 0, 0]\nmax = [10, 10, 10]\n".to_string();
    for (name, z) in names.iter().zip([3, 6]) {
        text += "[[joints]]\ntype = \"plane\"\ndip = 0\ndip_direction = 0\n";
        text += &format!("point = [0, 0, {z}]\n");
        if let Some(name) = name {
            text += &format!("name = {name:?}\n");
        }
    }
    text
}

/// The field and message of generating `text`'s spec, which must fail.
fn refused(text: &str) -> (String, String) {
    match generate(&parse_toml(text).unwrap()) {
        Err(GenerationError::Spec(e)) => (e.field.clone(), e.to_string()),
        other => panic!("{:?}", other.map(|g| g.system.len())),
    }
}

#[test]
fn a_spec_with_a_name_given_twice_or_holding_the_separator_is_refused() {
    let (field, message) = refused(&spec([Some("J1"), Some("J1")]));
    assert_eq!(field, "joints[1].name");
    assert!(
        message.contains("\"J1\" is already that of joints[0]"),
        "{message}"
    );
    let (field, message) = refused(&spec([Some("J1"), Some("J2|J3")]));
    assert_eq!(field, "joints[1].name");
    assert!(message.contains("\"J2|J3\" holds `|`"), "{message}");
    // A name that is another entry's default name.
    let (field, message) = refused(&spec([Some("joints[1]"), None]));
    assert_eq!(field, "joints[1].name");
    assert!(message.contains("already that of joints[0]"), "{message}");
    // Distinct names, and no names at all, are kept.
    for names in [[Some("J1"), Some("J2")], [None, None]] {
        let system = generate(&parse_toml(&spec(names)).unwrap()).unwrap().system;
        assert_eq!(system.len(), 3);
    }
}

#[test]
fn a_spec_with_a_name_the_contact_table_uses_for_other_faces_is_refused() {
    // The contact table's own labels (set_a, set_b): a domain face, a rock-bridge face, a
    // face with no recorded origin. They were accepted, and the table read ambiguously.
    let cases = [
        ("boundary", "of a face on the domain's surface"),
        ("bridge of J2", "label of a rock-bridge face"),
        ("bridge of ", "label of a rock-bridge face"),
        ("", "is empty"),
        ("   ", "is empty"),
    ];
    for (name, why) in cases {
        let (field, message) = refused(&spec([Some("J1"), Some(name)]));
        assert_eq!(field, "joints[1].name", "{name:?}");
        assert!(message.contains(why), "{name:?}: {message}");
        assert!(message.contains("choose another"), "{name:?}: {message}");
    }
    // Names that only look alike are kept.
    for name in [
        "Boundary",
        "boundary 2",
        "bridge",
        "a bridge of J2",
        "bridge ofJ2",
    ] {
        let system = generate(&parse_toml(&spec([Some("J1"), Some(name)])).unwrap())
            .unwrap()
            .system;
        assert_eq!(system.len(), 3, "{name:?}");
    }
    // And so is a block file's set of such a name.
    let (field, message) = format_error(&file_with_sets(["A", "boundary"]));
    assert_eq!(field, "sets[1].name");
    assert!(
        message.contains("\"boundary\" is the contact table's label"),
        "{message}"
    );
}

/// The block file of the two-plane spec, its set names replaced by `names`.
fn file_with_sets(names: [&str; 2]) -> String {
    let system = generate(&parse_toml(&spec([Some("A"), Some("B")])).unwrap())
        .unwrap()
        .system;
    let mut value: serde_json::Value = serde_json::from_str(&to_json_string(&system)).unwrap();
    for (set, name) in value["sets"].as_array_mut().unwrap().iter_mut().zip(names) {
        set["name"] = name.into();
    }
    value.to_string()
}

fn format_error(text: &str) -> (String, String) {
    match from_json_str(text) {
        Err(e @ IoError::Format { .. }) => {
            let IoError::Format { ref field, .. } = e else {
                unreachable!()
            };
            (field.clone(), e.to_string())
        }
        other => panic!("{:?}", other.map(|s| s.len())),
    }
}

#[test]
fn a_block_file_with_a_set_name_given_twice_or_holding_the_separator_is_refused() {
    assert_eq!(from_json_str(&file_with_sets(["A", "B"])).unwrap().len(), 3);
    let (field, message) = format_error(&file_with_sets(["A", "A"]));
    assert_eq!(field, "sets[1].name");
    assert!(
        message.contains("\"A\" is already that of sets[0]"),
        "{message}"
    );
    let (field, message) = format_error(&file_with_sets(["A|B", "B"]));
    assert_eq!(field, "sets[0].name");
    assert!(message.contains("\"A|B\" holds `|`"), "{message}");
}

/// A block file with `unit`.
fn file_with_unit(unit: &str) -> String {
    let mut value: serde_json::Value = serde_json::from_str(&file_with_sets(["A", "B"])).unwrap();
    value["unit"] = unit.into();
    value.to_string()
}

#[test]
fn a_block_file_takes_the_units_name_of_a_spec_and_no_other() {
    let longest = "f".repeat(MAX_UNIT_CHARS);
    for unit in ["m", "ft", longest.as_str()] {
        let system = from_json_str(&file_with_unit(unit)).unwrap();
        assert_eq!(system.unit(), Some(unit));
    }
    let huge = "x".repeat(1 << 20);
    let too_long = "f".repeat(MAX_UNIT_CHARS + 1);
    for unit in [too_long.as_str(), "", "  ", "m\u{7}", huge.as_str()] {
        let (field, message) = format_error(&file_with_unit(unit));
        assert_eq!(field, "unit");
        assert!(
            message.contains("must be a short name of a length unit"),
            "{message}"
        );
        // The message quotes at most the name's start: a megabyte makes a short line.
        assert!(message.len() < 300, "{} bytes", message.len());
    }
    // The spec's rule is the same one.
    let text = format!("unit = {too_long:?}\n{}", spec([None, None]));
    let err = parse_toml(&text).unwrap_err();
    assert_eq!(err.field, "unit");
}

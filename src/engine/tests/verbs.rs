//! The action library's table: a verb's validation names its field, the library refuses loops
//! and phrases that name two verbs, and the default library round-trips through its written form.

use crate::engine::action::{ActionInput, Library};

fn input(json: &str) -> ActionInput {
    serde_json::from_str(json).unwrap()
}

#[test]
fn the_default_library_round_trips_through_its_written_form() {
    let library = Library::default_library();
    for def in library.verbs() {
        let written = def.to_input();
        assert_eq!(&written.validate(&def.name).unwrap(), def, "{}", def.name);
    }
}

#[test]
fn validation_names_the_field_at_fault() {
    let cases = [
        (r#"{"parameters": ["x"], "methods": [{}]}"#, "/parameters/0"),
        (r#"{"parameters": ["X", "X"], "methods": [{}]}"#, "/parameters/1"),
        (r#"{"parameters": ["X"], "methods": []}"#, "/methods"),
        (
            r#"{"parameters": ["X"], "methods": [{"adds": ["open(Y)"]}]}"#,
            "/methods/0/adds/0",
        ),
        (
            r#"{"parameters": ["X"], "methods": [{"reach": ["Y"]}]}"#,
            "/methods/0/reach/0",
        ),
        (
            r#"{"parameters": ["X"], "methods": [{"steps": ["open(X)"]}]}"#,
            "/methods/0/steps/0",
        ),
        (
            r#"{"parameters": ["X"], "methods": [{"steps": ["itself", "itself"]}]}"#,
            "/methods/0/steps/1",
        ),
        (
            r#"{"parameters": ["X"], "methods": [{"preconditions": ["closed("]}]}"#,
            "/methods/0/preconditions/0",
        ),
        (
            r#"{"parameters": ["X"], "methods": [{"place": ["X"]}]}"#,
            "/methods/0/place",
        ),
        (r#"{"name": "shut", "parameters": ["X"], "methods": [{}]}"#, "/name"),
    ];
    for (json, field) in cases {
        let err = input(json).validate("open").unwrap_err();
        assert_eq!(err.field, field, "{json}: {err}");
    }
    assert_eq!(
        input(r#"{"methods": [{}]}"#).validate("Open").unwrap_err().field,
        "/name"
    );
}

#[test]
fn recursion_through_the_library_is_refused_and_leaves_it_unchanged() {
    let mut library = Library::default_library();
    let fetch = input(r#"{"parameters": ["X"], "methods": [{"steps": ["carry(X)"]}]}"#)
        .validate("fetch")
        .unwrap();
    library.insert(fetch).unwrap();
    let carry = input(r#"{"parameters": ["X"], "methods": [{"steps": ["fetch(X)"]}]}"#)
        .validate("carry")
        .unwrap();
    let err = library.insert(carry).unwrap_err();
    assert!(err.message.contains("carry → fetch → carry"), "{err}");
    assert!(library.get("carry", 1).is_none());
}

#[test]
fn a_verbs_words_and_joiners_are_checked_and_normalised() {
    let cases = [
        (r#"{"parameters": ["X"], "methods": [{}], "words": ["pick  UP"]}"#, None),
        (
            r#"{"parameters": ["X"], "methods": [{}], "words": ["pick-up"]}"#,
            Some("/words/0"),
        ),
        (
            r#"{"parameters": ["X"], "methods": [{}], "words": ["a b c d"]}"#,
            Some("/words/0"),
        ),
        (
            r#"{"parameters": ["X"], "methods": [{}], "words": ["open", "Open"]}"#,
            Some("/words/1"),
        ),
        (
            r#"{"parameters": ["X"], "methods": [{}], "words": [""]}"#,
            Some("/words/0"),
        ),
        (
            r#"{"parameters": ["X", "Y"], "methods": [{}], "joiners": ["into"]}"#,
            None,
        ),
        (
            r#"{"parameters": ["X", "Y"], "methods": [{}], "joiners": ["in to"]}"#,
            Some("/joiners/0"),
        ),
        (
            r#"{"parameters": ["X"], "methods": [{}], "joiners": ["on"]}"#,
            Some("/joiners"),
        ),
    ];
    for (json, field) in cases {
        let outcome = input(json).validate("open");
        assert_eq!(
            outcome.as_ref().err().map(|e| e.field.as_str()),
            field,
            "{json}: {outcome:?}"
        );
    }
    let def = input(r#"{"parameters": ["X"], "methods": [{}], "words": [" Pick   up "]}"#)
        .validate("open")
        .unwrap();
    assert_eq!(def.words, ["pick up"]);
}

#[test]
fn a_phrase_names_one_verb_and_the_clash_is_told_on_the_verb_being_stored() {
    let mut library = Library::default_library();
    assert!(library.check_words("").is_ok(), "the default words are disjoint");
    let grab = input(r#"{"parameters": ["X"], "methods": [{}], "words": ["seize", "grab"]}"#)
        .validate("clutch")
        .unwrap();
    library.insert(grab).unwrap();
    let (verb, err) = library.check_words("clutch").unwrap_err();
    assert_eq!(verb, "clutch");
    assert_eq!(err.field, "/words/1");
    assert_eq!(err.message, "`grab` already names the verb `get`");
    // Loading, with no verb being stored, still refuses the clash.
    assert!(library.check_words("").is_err());
}

/// Issue 50, §3.10: `snatch` could take "grabbed" while "grab" names `get` ("Grabbed the cup."
/// was `get`), and "the", "please", "can", "go" were accepted as verb words and "and" as a
/// joiner.
#[test]
fn verb_words_that_clash_once_inflected_or_are_the_grammars_own_are_refused() {
    let verb = |json: &str| serde_json::from_str::<crate::engine::action::ActionInput>(json).unwrap();
    let mut library = Library::default_library();
    let snatch = verb(r#"{"parameters": ["X"], "methods": [{}], "words": ["grabbed"]}"#)
        .validate("snatch")
        .unwrap();
    library.insert(snatch).unwrap();
    let (at, err) = library.check_words("snatch").unwrap_err();
    assert_eq!(at, "snatch");
    assert_eq!(err.field, "/words/0");
    assert_eq!(
        err.message,
        "`grabbed` and `grab` are forms of one word, and `grab` names the verb `get`"
    );
    // A library stored before the rule still loads: only exact clashes are refused on reading.
    assert!(library.check_words("").is_ok());
    for word in ["the", "please", "can", "go", "now", "and"] {
        let json = format!(r#"{{"parameters": ["X"], "methods": [{{}}], "words": ["{word} it"]}}"#);
        let err = verb(&json).validate("odd").unwrap().check_written_words().unwrap_err();
        assert_eq!(err.field, "/words/0", "{word}");
    }
    for joiner in ["and", "then", "the", "or"] {
        let json =
            format!(r#"{{"parameters": ["X", "Y"], "methods": [{{}}], "words": ["fling"], "joiners": ["{joiner}"]}}"#);
        let err = verb(&json)
            .validate("fling")
            .unwrap()
            .check_written_words()
            .unwrap_err();
        assert_eq!(err.field, "/joiners/0", "{joiner}");
    }
}

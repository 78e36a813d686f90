//! The playground page and its assets: served from the binary, typed, and its paper preset
//! kept equal to `../shared/scenarios/paper-demo.json`.

use reqwest::StatusCode;
use serde_json::Value;

use crate::helpers::{paper_demo, spawn_app};

#[tokio::test]
async fn the_page_and_its_assets_are_served_with_their_types() {
    let app = spawn_app().await;
    for (path, content_type, needle) in [
        ("/", "text/html; charset=utf-8", "/playground/app.js"),
        ("/playground/app.js", "text/javascript; charset=utf-8", "/v1/clarify"),
        ("/playground/style.css", "text/css; charset=utf-8", ":focus-visible"),
    ] {
        let response = app.get(path).await;
        assert_eq!(response.status(), StatusCode::OK, "{path}");
        let headers = response.headers().clone();
        assert_eq!(headers["content-type"], content_type, "{path}");
        assert_eq!(headers["cache-control"], "no-cache", "{path}");
        assert_eq!(headers["x-content-type-options"], "nosniff", "{path}");
        assert!(headers.contains_key("content-security-policy"), "{path}");
        let body = response.text().await.unwrap();
        assert!(body.contains(needle), "{path} lacks {needle}");
    }
    app.stop().await;
}

/// The preset sits in `app.js` between two markers as a JSON literal, so it can be compared.
#[test]
fn the_paper_preset_is_the_paper_scenario() {
    let script = include_str!("../../playground/app.js");
    let begin = "/* paper-demo:begin */";
    let end = "/* paper-demo:end */";
    let start = script.find(begin).expect("begin marker") + begin.len();
    let stop = script.find(end).expect("end marker");
    let preset: Value = serde_json::from_str(&script[start..stop]).expect("the preset is JSON");
    let demo = paper_demo();
    assert_eq!(preset["norms"], demo["norms"]);
    assert_eq!(preset["scenes"], demo["scenes"]);
    assert_eq!(preset["cases"], demo["cases"]);
}

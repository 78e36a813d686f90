//! The load benchmark's floor (bench-only, not part of the product): a minimal server on one
//! port that decodes the same clarify request types and encodes the same response types as
//! Scruple (REST JSON and gRPC protobuf), with no engine, no store and no validation.
//! `scripts/bench-load.sh` measures Scruple against it.
//!
//! With `--value`, REST is the stricter floor an outside check uses: the body decoded into a
//! `serde_json::Value` (no typed request), and the answer's bytes, encoded once, sent again.
//!
//! Either way the answer is the one Scruple gives the bench's request, byte for byte: to the
//! directive sent as text alone it carries `parse`, as Scruple's does (148 bytes more).
//!
//! Usage: `cargo run --release --example floor -- 127.0.0.1:0 [--value]` (prints `listening on ADDR`).

use axum::body::Bytes;
use axum::http::header::CONTENT_TYPE;
use axum::routing::post;
use axum::{Json, Router};
use scruple::transport::grpc::pb;
use scruple::transport::grpc::pb::clarifier_server::{Clarifier, ClarifierServer};
use scruple::wire::{ClarifyBody, DecisionDto, InterpretationDto, ParseDto, ReasonDto, ReferenceParseDto};
use tonic::{Request, Response, Status};

/// Answers every Clarify with the same decision, after decoding the request.
struct Floor(DecisionDto);

#[tonic::async_trait]
impl Clarifier for Floor {
    async fn clarify(&self, request: Request<pb::ClarifyRequest>) -> Result<Response<pb::ClarifyResponse>, Status> {
        let mut answer = self.0.clone();
        answer.text = request.into_inner().directive.and_then(|d| d.text);
        Ok(Response::new(answer.into()))
    }

    async fn check(&self, _: Request<pb::CheckRequest>) -> Result<Response<pb::CheckResponse>, Status> {
        Err(Status::unimplemented("the floor measures Clarify only"))
    }
}

/// How Scruple reads "Get the vase." sent as text alone: its answer to that directive says so.
fn parse() -> ParseDto {
    ParseDto {
        act: "command".into(),
        addressee: None,
        form: Some("want(human,did(self,get(X)))".into()),
        references: vec![ReferenceParseDto {
            words: "the vase".into(),
            candidates: vec!["object3".into(), "object4".into()],
        }],
        ignored: vec![],
        unclear: None,
        steps: vec![],
        purposes: vec![],
    }
}

/// The answer to the paper's "Get the vase." sent structured, built once; every request gets
/// a copy of it (with `parse` added when sent as text alone).
fn answer() -> DecisionDto {
    let reading = |action: &str, description: &str, ok: bool| InterpretationDto {
        action: format!("did(self,get({action}))"),
        description: description.to_owned(),
        permissible: ok,
        feasible: true,
        reasons: if ok {
            vec![]
        } else {
            vec![ReasonDto {
                kind: "forbidden_state".into(),
                detail: format!("did(self,get({action}))"),
                norm_id: Some(2),
                severity: Some(3),
                words: "it requires a forbidden state".into(),
            }]
        },
        plan: vec![format!("get({action})")],
        score: 1.0,
        norm_score: 0,
    };
    DecisionDto {
        decision: "assume".into(),
        utterance: "I am assuming you want me to get the plastic vase. I cannot get the fragile vase because it requires a forbidden state.".into(),
        speech_act: "assume(self,mean(human,did(self,get(object4))))".into(),
        goal: Some("did(self,get(object4))".into()),
        interpretations: vec![reading("object3", "the fragile vase", false), reading("object4", "the plastic vase", true)],
        offered: vec!["did(self,get(object4))".into()],
        limits: None,
        norm_version: 3,
        library_version: 1,
        text: None,
        parse: None,
        alternative: None,
    }
}

#[tokio::main]
async fn main() {
    let mut args = std::env::args().skip(1);
    let addr = args.next().unwrap_or_else(|| "127.0.0.1:0".to_owned());
    let value = match args.next().as_deref() {
        None => false,
        Some("--value") => true,
        Some(other) => {
            eprintln!("floor: unknown argument {other:?}; usage: floor [ADDR] [--value]");
            std::process::exit(2);
        }
    };
    let answer = answer();
    // The answer to the directive sent as text alone (no action, no form): Scruple's says how
    // it read the words.
    let in_words = |answer: &DecisionDto| DecisionDto {
        parse: Some(parse()),
        ..answer.clone()
    };
    let grpc = tonic::service::Routes::new(ClarifierServer::new(Floor(answer.clone()))).into_axum_router();
    let app = Router::new().merge(grpc);
    let app = if value {
        // The typed floor's answers to the bench's two bodies (whose text is the paper's), as
        // bytes: the one to the text alone when the directive has neither action nor form.
        let encode = |answer: DecisionDto| {
            Bytes::from(
                serde_json::to_vec(&DecisionDto {
                    text: Some("Get the vase.".into()),
                    ..answer
                })
                .expect("encode"),
            )
        };
        let (structured, words) = (encode(answer.clone()), encode(in_words(&answer)));
        app.route(
            "/v1/clarify",
            post(move |Json(body): Json<serde_json::Value>| {
                let directive = &body["directive"];
                let bytes = match directive.get("action").is_none() && directive.get("form").is_none() {
                    true => words.clone(),
                    false => structured.clone(),
                };
                async move { ([(CONTENT_TYPE, "application/json")], bytes) }
            }),
        )
    } else {
        let words = in_words(&answer);
        app.route(
            "/v1/clarify",
            post(move |Json(body): Json<ClarifyBody>| {
                let directive = body.directive;
                let mut answer = match directive.action.is_none() && directive.form.is_none() {
                    true => words.clone(),
                    false => answer.clone(),
                };
                answer.text = directive.text;
                async move { Json(answer) }
            }),
        )
    };
    let listener = tokio::net::TcpListener::bind(&addr).await.expect("bind");
    println!("listening on {}", listener.local_addr().expect("bound"));
    // TCP_NODELAY, as Scruple sets it: the floor must not be slowed by what Scruple is not.
    let listener = axum::serve::ListenerExt::tap_io(listener, |tcp| {
        let _ = tcp.set_nodelay(true);
    });
    axum::serve(listener, app).await.expect("serve");
}

//! A gRPC client of a running Scruple: adds the paper's norm ("the fragile vase may not be got"),
//! asks it to "Get the vase." in the paper's lab, and prints what the robot would say.
//!
//! Usage: `cargo run --example client -- 127.0.0.1:PORT` (the address `scruple serve` prints).
//! When the server needs a token for writes, set `SCRUPLE_ADMIN_TOKEN`. Exits nonzero unless the
//! decision is the paper's: assume the plastic vase.

use std::process::ExitCode;

use scruple::transport::grpc::pb;
use scruple::transport::grpc::pb::clarifier_client::ClarifierClient;
use scruple::transport::grpc::pb::norms_client::NormsClient;
use tonic::Request;
use tonic::metadata::MetadataValue;
use tonic::transport::Channel;

const EXPECTED: &str = "I am assuming you want me to get the plastic vase. \
                        I cannot get the fragile vase because it requires a forbidden state.";

/// A vase, metres in the world frame: both stand on the table within the arm's 0.9 m reach.
fn vase(id: &str, y: f64, properties: &[&str], attributes: &[(&str, &str)]) -> pb::Object {
    pb::Object {
        id: id.to_owned(),
        r#type: "vase".to_owned(),
        properties: properties.iter().map(|p| (*p).to_owned()).collect(),
        attributes: attributes
            .iter()
            .map(|(k, v)| ((*k).to_owned(), (*v).to_owned()))
            .collect(),
        position: vec![0.6, y, 0.85],
        shape: Some(pb::Shape {
            kind: Some(pb::shape::Kind::Cylinder(pb::Cylinder {
                radius: 0.06,
                half_height: 0.1,
            })),
        }),
        ..Default::default()
    }
}

/// The vases of the paper's lab (object3 and object4 of `paper-demo.json`).
fn lab_scene() -> pb::Scene {
    pb::Scene {
        agent: Some(pb::Agent {
            id: Some("self".to_owned()),
            position: vec![0.0, 0.0, 0.75],
            reach: Some(0.9),
            ..Default::default()
        }),
        objects: vec![
            vase("object3", 0.15, &["fragile"], &[]),
            vase("object4", 0.35, &[], &[("material", "plastic")]),
        ],
        facts: vec![],
        people: vec![],
    }
}

async fn run(address: &str) -> Result<bool, Box<dyn std::error::Error>> {
    let uri = if address.contains("://") {
        address.to_owned()
    } else {
        format!("http://{address}")
    };
    let channel = Channel::from_shared(uri)?.connect().await?;

    let mut create = Request::new(pb::CreateNormRequest {
        kind: Some("forbidden_state".to_owned()),
        state: Some("did(self,get(object3))".to_owned()),
        note: Some("the fragile vase may not be got".to_owned()),
        ..Default::default()
    });
    if let Ok(token) = std::env::var("SCRUPLE_ADMIN_TOKEN") {
        let value: MetadataValue<_> = format!("Bearer {token}").parse()?;
        create.metadata_mut().insert("authorization", value);
    }
    let norm = NormsClient::new(channel.clone())
        .create_norm(create)
        .await?
        .into_inner();
    println!("norm {}: {} {}", norm.id, norm.kind, norm.state.unwrap_or_default());

    let request = pb::ClarifyRequest {
        directive: Some(pb::Directive {
            action: Some("get".to_owned()),
            arguments: vec![pb::Reference {
                r#type: Some("vase".to_owned()),
                ..Default::default()
            }],
            text: Some("Get the vase.".to_owned()),
            ..Default::default()
        }),
        scene: Some(lab_scene()),
        ..Default::default()
    };
    let answer = ClarifierClient::new(channel).clarify(request).await?.into_inner();
    println!("decision: {}", answer.decision);
    println!("utterance: {}", answer.utterance);
    Ok(answer.decision == "assume" && answer.utterance == EXPECTED)
}

#[tokio::main]
async fn main() -> ExitCode {
    let Some(address) = std::env::args().nth(1) else {
        eprintln!("usage: client HOST:PORT");
        return ExitCode::from(2);
    };
    match run(&address).await {
        Ok(true) => ExitCode::SUCCESS,
        Ok(false) => {
            eprintln!("client: expected: assume, \"{EXPECTED}\"");
            ExitCode::FAILURE
        }
        Err(e) => {
            eprintln!("client: {e}");
            ExitCode::FAILURE
        }
    }
}

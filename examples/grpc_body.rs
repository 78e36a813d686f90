//! Writes the paper's "Get the vase." as a framed gRPC request body (flag byte, 4-byte length,
//! protobuf), for h2load in `scripts/bench-load.sh`. Usage: `grpc_body FILE`.

use prost::Message;
use scruple::transport::grpc::pb;

fn main() {
    let path = std::env::args().nth(1).expect("usage: grpc_body FILE");
    let demo: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../shared/scenarios/paper-demo.json"
        ))
        .expect("paper-demo.json"),
    )
    .expect("JSON");
    let lab = &demo["scenes"]["lab"];
    let objects = lab["objects"]
        .as_array()
        .expect("objects")
        .iter()
        .map(|o| {
            let numbers = |v: &serde_json::Value| {
                v.as_array()
                    .map(|a| a.iter().filter_map(|n| n.as_f64()).collect())
                    .unwrap_or_default()
            };
            let shape = &o["shape"];
            let kind = if let Some(c) = shape.get("cylinder") {
                pb::shape::Kind::Cylinder(pb::Cylinder {
                    radius: c["radius"].as_f64().unwrap(),
                    half_height: c["half_height"].as_f64().unwrap(),
                })
            } else {
                pb::shape::Kind::Cuboid(pb::Cuboid {
                    half_extents: numbers(&shape["cuboid"]["half_extents"]),
                })
            };
            pb::Object {
                id: o["id"].as_str().unwrap().into(),
                r#type: o["type"].as_str().unwrap().into(),
                properties: o["properties"]
                    .as_array()
                    .map(|a| a.iter().map(|p| p.as_str().unwrap().into()).collect())
                    .unwrap_or_default(),
                attributes: o["attributes"]
                    .as_object()
                    .map(|m| m.iter().map(|(k, v)| (k.clone(), v.as_str().unwrap().into())).collect())
                    .unwrap_or_default(),
                position: numbers(&o["position"]),
                shape: Some(pb::Shape { kind: Some(kind) }),
                ..Default::default()
            }
        })
        .collect();
    let request = pb::ClarifyRequest {
        directive: Some(pb::Directive {
            action: Some("get".into()),
            arguments: vec![pb::Reference {
                r#type: Some("vase".into()),
                ..Default::default()
            }],
            text: Some("Get the vase.".into()),
            ..Default::default()
        }),
        scene: Some(pb::Scene {
            agent: Some(pb::Agent {
                id: Some("self".into()),
                position: vec![0.0, 0.0, 0.75],
                reach: Some(0.9),
                ..Default::default()
            }),
            objects,
            facts: vec![],
        }),
        ..Default::default()
    };
    let message = request.encode_to_vec();
    let mut framed = vec![0u8];
    framed.extend_from_slice(&(message.len() as u32).to_be_bytes());
    framed.extend_from_slice(&message);
    std::fs::write(&path, framed).expect("write");
}

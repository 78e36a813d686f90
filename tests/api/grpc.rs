//! gRPC on the same port as REST: the same decisions, the same errors, health and reflection.

use std::collections::HashMap;

use reqwest::StatusCode;
use scruple::transport::grpc::pb;
use scruple::transport::grpc::pb::clarifier_client::ClarifierClient;
use scruple::transport::grpc::pb::norms_client::NormsClient;
use serde_json::{Value, json};
use tonic::Code;
use tonic::transport::Channel;

use crate::helpers::{Options, TestApp, assert_problem, get_vase, lab_scene, paper_demo, spawn_app, spawn_with};

pub(crate) async fn channel(app: &TestApp) -> Channel {
    Channel::from_shared(app.base.clone())
        .unwrap()
        .connect()
        .await
        .expect("gRPC connects to the REST port")
}

fn strings(v: &Value) -> Vec<String> {
    v.as_array()
        .map(|a| a.iter().map(|s| s.as_str().unwrap().to_owned()).collect())
        .unwrap_or_default()
}

fn numbers(v: &Value) -> Vec<f64> {
    v.as_array()
        .map(|a| a.iter().map(|n| n.as_f64().unwrap()).collect())
        .unwrap_or_default()
}

/// A reference in JSON as its message, relations and all.
fn reference(r: &Value) -> pb::Reference {
    pb::Reference {
        id: opt(&r["id"]),
        r#type: opt(&r["type"]),
        attributes: string_map(&r["attributes"]),
        properties: strings(&r["properties"]),
        relations: (r["relations"].as_array().into_iter().flatten())
            .map(|rel| pb::Relation {
                relation: rel["relation"].as_str().unwrap_or_default().to_owned(),
                to: rel.get("to").map(reference),
            })
            .collect(),
        count: r["count"].as_u64(),
        all: r["all"].as_bool(),
    }
}

fn string_map(v: &Value) -> HashMap<String, String> {
    v.as_object()
        .map(|m| {
            m.iter()
                .map(|(k, v)| (k.clone(), v.as_str().unwrap().to_owned()))
                .collect()
        })
        .unwrap_or_default()
}

fn opt(v: &Value) -> Option<String> {
    v.as_str().map(str::to_owned)
}

/// The REST JSON of a clarify request, as the same proto message a gRPC client would build.
pub(crate) fn clarify_request(body: &Value) -> pb::ClarifyRequest {
    let directive = &body["directive"];
    let scene = &body["scene"];
    let objects = scene["objects"]
        .as_array()
        .unwrap()
        .iter()
        .map(|o| pb::Object {
            id: o["id"].as_str().unwrap().to_owned(),
            r#type: o["type"].as_str().unwrap().to_owned(),
            properties: strings(&o["properties"]),
            attributes: string_map(&o["attributes"]),
            position: numbers(&o["position"]),
            shape: o.get("shape").map(|s| pb::Shape {
                kind: Some(if let Some(c) = s.get("cylinder") {
                    pb::shape::Kind::Cylinder(pb::Cylinder {
                        radius: c["radius"].as_f64().unwrap(),
                        half_height: c["half_height"].as_f64().unwrap(),
                    })
                } else if let Some(c) = s.get("cuboid") {
                    pb::shape::Kind::Cuboid(pb::Cuboid {
                        half_extents: numbers(&c["half_extents"]),
                    })
                } else {
                    pb::shape::Kind::Ball(pb::Ball {
                        radius: s["ball"]["radius"].as_f64().unwrap(),
                    })
                }),
            }),
            rotation: numbers(&o["rotation"]),
            mass: o["mass"].as_f64(),
            names: strings(&o["names"]),
        })
        .collect();
    let bindings = directive["bindings"]
        .as_object()
        .map(|m| {
            m.iter()
                .map(|(variable, list)| {
                    let candidates = list
                        .as_array()
                        .unwrap()
                        .iter()
                        .map(|c| match c.as_str() {
                            Some(id) => pb::Candidate {
                                id: id.to_owned(),
                                score: None,
                            },
                            None => pb::Candidate {
                                id: c["id"].as_str().unwrap().to_owned(),
                                score: c["score"].as_f64(),
                            },
                        })
                        .collect();
                    (variable.clone(), pb::Candidates { candidates })
                })
                .collect()
        })
        .unwrap_or_default();
    pb::ClarifyRequest {
        speaker: opt(&body["speaker"]),
        directive: Some(pb::Directive {
            action: opt(&directive["action"]),
            arguments: directive["arguments"]
                .as_array()
                .map(|args| args.iter().map(reference).collect())
                .unwrap_or_default(),
            form: opt(&directive["form"]),
            bindings,
            text: opt(&directive["text"]),
            joiner: opt(&directive["joiner"]),
            steps: directive["steps"]
                .as_array()
                .map(|steps| {
                    steps
                        .iter()
                        .map(|s| pb::Step {
                            action: s["action"].as_str().unwrap_or_default().to_owned(),
                            arguments: (s["arguments"].as_array().into_iter().flatten())
                                .map(|a| pb::StepArgument {
                                    id: opt(&a["id"]),
                                    r#type: opt(&a["type"]),
                                    attributes: string_map(&a["attributes"]),
                                    properties: strings(&a["properties"]),
                                    relations: reference(a).relations,
                                    count: a["count"].as_u64(),
                                    all: a["all"].as_bool(),
                                    step: a["step"].as_u64(),
                                    argument: a["argument"].as_u64(),
                                })
                                .collect(),
                            joiner: opt(&s["joiner"]),
                        })
                        .collect()
                })
                .unwrap_or_default(),
        }),
        scene: Some(pb::Scene {
            agent: Some(pb::Agent {
                id: opt(&scene["agent"]["id"]),
                position: numbers(&scene["agent"]["position"]),
                reach: scene["agent"]["reach"].as_f64(),
                gripper_aperture: scene["agent"]["gripper_aperture"].as_f64(),
                payload: scene["agent"]["payload"].as_f64(),
                gripper_size: scene["agent"]["gripper_size"].as_f64(),
                rotation: numbers(&scene["agent"]["rotation"]),
            }),
            objects,
            facts: strings(&scene["facts"]),
            people: (scene["people"].as_array().into_iter().flatten())
                .map(|p| pb::Person {
                    id: p["id"].as_str().unwrap_or_default().to_owned(),
                    names: strings(&p["names"]),
                    roles: strings(&p["roles"]),
                    position: numbers(&p["position"]),
                })
                .collect(),
        }),
        context: opt(&body["context"]),
        options: body.get("options").map(|o| pb::Options {
            strategy: opt(&o["strategy"]),
            single_permissible: opt(&o["single_permissible"]),
            style: opt(&o["style"]),
            max_spoken: o["max_spoken"].as_u64(),
            max_readings: o["max_readings"].as_u64(),
            deadline_ms: o["deadline_ms"].as_u64(),
            confirm_above_ratio: o["confirm_above_ratio"].as_f64(),
            soft_norms: opt(&o["soft_norms"]),
            alternatives: opt(&o["alternatives"]),
        }),
        speaker_roles: strings(&body["speaker_roles"]),
        answer: body.get("answer").map(|a| pb::Answer {
            choice: a["choice"].as_u64(),
            alternative: a["choice"] == "alternative",
            id: opt(&a["id"]),
            reference: a.get("reference").map(reference),
            text: opt(&a["text"]),
        }),
        focus: strings(&body["focus"]),
    }
}

/// A gRPC answer in the REST answer's JSON shape, to compare the two field for field.
pub(crate) fn as_rest_json(r: pb::ClarifyResponse) -> Value {
    let interpretations: Vec<Value> = r
        .interpretations
        .into_iter()
        .map(|i| {
            let reasons: Vec<Value> = i
                .reasons
                .into_iter()
                .map(|reason| {
                    let mut v = json!({"kind": reason.kind, "detail": reason.detail});
                    if let Some(id) = reason.norm_id {
                        v["norm_id"] = json!(id);
                    }
                    if let Some(severity) = reason.severity {
                        v["severity"] = json!(severity);
                    }
                    v["words"] = json!(reason.words);
                    v
                })
                .collect();
            let mut v = json!({"action": i.action, "description": i.description, "permissible": i.permissible,
                               "feasible": i.feasible, "reasons": reasons, "plan": i.plan, "score": i.score});
            if i.norm_score != 0 {
                v["norm_score"] = json!(i.norm_score);
            }
            v
        })
        .collect();
    let mut v = json!({"decision": r.decision, "utterance": r.utterance, "speech_act": r.speech_act,
                       "goal": r.goal, "interpretations": interpretations, "offered": r.offered,
                       "norm_version": r.norm_version, "library_version": r.library_version});
    if let Some(limits) = r.limits {
        v["limits"] = json!({"reason": limits.reason, "readings": limits.readings, "simulated": limits.simulated});
    }
    if let Some(text) = r.text {
        v["text"] = json!(text);
    }
    if let Some(alternative) = r.alternative {
        v["alternative"] = json!(alternative);
    }
    if let Some(p) = r.parse {
        let references: Vec<Value> = (p.references.into_iter())
            .map(|r| json!({"words": r.words, "candidates": r.candidates}))
            .collect();
        let mut parse = json!({"act": p.act, "references": references, "ignored": p.ignored});
        for (key, value) in [("addressee", p.addressee), ("form", p.form), ("unclear", p.unclear)] {
            if let Some(value) = value {
                parse[key] = json!(value);
            }
        }
        if !p.steps.is_empty() {
            let steps: Vec<Value> = (p.steps.into_iter())
                .map(|s| {
                    let references: Vec<Value> = (s.references.into_iter())
                        .map(|r| json!({"words": r.words, "candidates": r.candidates}))
                        .collect();
                    let mut step = json!({"act": s.act, "form": s.form, "references": references});
                    if !s.pronouns.is_empty() {
                        let pronouns: Vec<Value> = (s.pronouns.into_iter())
                            .map(|b| {
                                let mut bound =
                                    json!({"words": b.words, "argument": b.argument, "bound_to": b.bound_to});
                                if let Some(step) = b.step {
                                    bound["step"] = json!(step);
                                }
                                if let Some(argument) = b.step_argument {
                                    bound["step_argument"] = json!(argument);
                                }
                                if let Some(focus) = b.focus {
                                    bound["focus"] = json!(focus);
                                }
                                bound
                            })
                            .collect();
                        step["pronouns"] = json!(pronouns);
                    }
                    step
                })
                .collect();
            parse["steps"] = json!(steps);
        }
        if !p.purposes.is_empty() {
            let purposes: Vec<Value> = (p.purposes.into_iter())
                .map(|purpose| {
                    let mut v = json!({"words": purpose.words, "after": purpose.after});
                    if let Some(form) = purpose.form {
                        v["form"] = json!(form);
                    }
                    v
                })
                .collect();
            parse["purposes"] = json!(purposes);
        }
        v["parse"] = parse;
    }
    v
}

pub(crate) fn norm_request(norm: &Value) -> pb::CreateNormRequest {
    pb::CreateNormRequest {
        kind: opt(&norm["kind"]),
        action: opt(&norm["action"]),
        state: opt(&norm["state"]),
        when: strings(&norm["when"]),
        context: opt(&norm["context"]),
        severity: norm["severity"].as_i64(),
        note: opt(&norm["note"]),
        roles: strings(&norm["roles"]),
        exempt_roles: strings(&norm["exempt_roles"]),
    }
}

#[tokio::test]
async fn every_paper_case_gives_the_same_answer_over_grpc_as_over_rest() {
    let app = spawn_app().await;
    let channel = channel(&app).await;
    let mut norms = NormsClient::new(channel.clone());
    let mut clarifier = ClarifierClient::new(channel);
    let demo = paper_demo();
    // Norms added over gRPC are the norms REST decides under: one store, one core.
    for norm in demo["norms"].as_array().unwrap() {
        norms
            .create_norm(norm_request(norm))
            .await
            .expect("norm created over gRPC");
    }
    assert_eq!(app.norms().await.len(), 3);
    for case in demo["cases"].as_array().unwrap() {
        let mut directive = case["directive"].clone();
        directive["text"] = case["text"].clone();
        let mut body = json!({"directive": directive, "scene": demo["scenes"][case["scene"].as_str().unwrap()]});
        if let Some(options) = case.get("options") {
            body["options"] = options.clone();
        }
        let rest = app.clarify(&body).await;
        let grpc = as_rest_json(
            clarifier
                .clarify(clarify_request(&body))
                .await
                .expect("clarify over gRPC")
                .into_inner(),
        );
        assert_eq!(grpc, rest, "{}", case["name"]);
        for (key, expected) in case["expect"].as_object().unwrap() {
            assert_eq!(&grpc[key], expected, "{}: {key}", case["name"]);
        }
        // The human's words alone: the same decision, over gRPC as over REST.
        body["directive"] = json!({"text": case["text"]});
        let rest = app.clarify(&body).await;
        let grpc = as_rest_json(
            clarifier
                .clarify(clarify_request(&body))
                .await
                .expect("words over gRPC")
                .into_inner(),
        );
        assert_eq!(grpc, rest, "{} in words", case["name"]);
        for (key, expected) in case["expect"].as_object().unwrap() {
            assert_eq!(&grpc[key], expected, "{} in words: {key}", case["name"]);
        }
    }
}

#[tokio::test]
async fn errors_carry_the_same_code_and_field_on_both_transports() {
    let app = spawn_with(Options {
        admin_token: Some("s3cret-admin-token".into()),
        ..Options::default()
    })
    .await;
    let channel = channel(&app).await;
    let mut clarifier = ClarifierClient::new(channel.clone());
    let mut norms = NormsClient::new(channel);

    // Invalid input: 422 naming the field / INVALID_ARGUMENT naming the same field.
    let mut bad = get_vase();
    bad["directive"]["arguments"] = json!([{"id": "object9"}]);
    assert_problem(
        app.post("/v1/clarify", &bad).await,
        StatusCode::UNPROCESSABLE_ENTITY,
        Some("/directive/arguments/0/id"),
    )
    .await;
    let status = clarifier.clarify(clarify_request(&bad)).await.unwrap_err();
    assert_eq!(status.code(), Code::InvalidArgument);
    assert!(
        status.message().starts_with("/directive/arguments/0/id: "),
        "{}",
        status.message()
    );
    assert_eq!(status.metadata().get("field").unwrap(), "/directive/arguments/0/id");

    // A message proto3 cannot leave out on the REST side is missing: the same pointer.
    let mut no_scene = clarify_request(&get_vase());
    no_scene.scene = None;
    let status = clarifier.clarify(no_scene).await.unwrap_err();
    assert_eq!(status.code(), Code::InvalidArgument);
    assert_eq!(status.metadata().get("field").unwrap(), "/scene");

    // A member of fixed length, or a shape of no kind, in the second object: named as REST
    // names it (the pointer is made only for the error).
    type Edit = fn(&mut pb::Object);
    let edits: [(Edit, &str); 4] = [
        (|o| o.position.push(1.0), "/scene/objects/1/position"),
        (|o| o.rotation = vec![0.0, 0.0, 1.0], "/scene/objects/1/rotation"),
        (|o| o.shape = Some(pb::Shape { kind: None }), "/scene/objects/1/shape"),
        (
            |o| {
                o.shape = Some(pb::Shape {
                    kind: Some(pb::shape::Kind::Cuboid(pb::Cuboid {
                        half_extents: vec![0.1],
                    })),
                })
            },
            "/scene/objects/1/shape/cuboid/half_extents",
        ),
    ];
    for (edit, field) in edits {
        let mut request = clarify_request(&get_vase());
        edit(&mut request.scene.as_mut().unwrap().objects[1]);
        let status = clarifier.clarify(request).await.unwrap_err();
        assert_eq!(status.code(), Code::InvalidArgument, "{field}");
        assert_eq!(status.metadata().get("field").unwrap(), field);
    }

    // Not found: 404 / NOT_FOUND.
    assert_problem(app.get("/v1/norms/999").await, StatusCode::NOT_FOUND, None).await;
    let status = norms.get_norm(pb::GetNormRequest { id: 999 }).await.unwrap_err();
    assert_eq!(status.code(), Code::NotFound);

    // Missing and wrong token: 401 / UNAUTHENTICATED and 403 / PERMISSION_DENIED; nothing stored.
    let norm = json!({"kind": "forbidden_action", "action": "destroy"});
    assert_problem(app.post("/v1/norms", &norm).await, StatusCode::UNAUTHORIZED, None).await;
    let status = norms.create_norm(norm_request(&norm)).await.unwrap_err();
    assert_eq!(status.code(), Code::Unauthenticated);
    let mut wrong = tonic::Request::new(norm_request(&norm));
    wrong
        .metadata_mut()
        .insert("authorization", "Bearer guess".parse().unwrap());
    assert_eq!(
        norms.create_norm(wrong).await.unwrap_err().code(),
        Code::PermissionDenied
    );
    let status = norms
        .delete_norm(pb::DeleteNormRequest {
            id: 1,
            expected_revision: None,
        })
        .await
        .unwrap_err();
    assert_eq!(status.code(), Code::Unauthenticated);
    assert!(app.norms().await.is_empty());

    // With the token, the write goes through, and a bad norm is INVALID_ARGUMENT naming its field.
    let mut right = tonic::Request::new(norm_request(&norm));
    right
        .metadata_mut()
        .insert("authorization", "Bearer s3cret-admin-token".parse().unwrap());
    let created = norms
        .create_norm(right)
        .await
        .expect("created with the token")
        .into_inner();
    assert_eq!(
        (created.kind.as_str(), created.action.as_deref(), created.severity),
        ("forbidden_action", Some("destroy"), 3)
    );
    let mut bad_norm = tonic::Request::new(norm_request(
        &json!({"kind": "forbidden_action", "action": "destroy", "severity": 9}),
    ));
    bad_norm
        .metadata_mut()
        .insert("authorization", "Bearer s3cret-admin-token".parse().unwrap());
    let status = norms.create_norm(bad_norm).await.unwrap_err();
    assert_eq!(status.code(), Code::InvalidArgument);
    assert_eq!(status.metadata().get("field").unwrap(), "/severity");
    let listed = norms
        .list_norms(pb::ListNormsRequest {})
        .await
        .unwrap()
        .into_inner()
        .norms;
    assert_eq!(listed, vec![created.clone()]);
    let mut delete = tonic::Request::new(pb::DeleteNormRequest {
        id: created.id,
        expected_revision: None,
    });
    delete
        .metadata_mut()
        .insert("authorization", "Bearer s3cret-admin-token".parse().unwrap());
    norms.delete_norm(delete).await.expect("deleted with the token");
    assert!(app.norms().await.is_empty());
}

#[tokio::test]
async fn health_reports_serving_for_the_server_and_each_service() {
    let app = spawn_app().await;
    let mut health = tonic_health::pb::health_client::HealthClient::new(channel(&app).await);
    for service in ["", "scruple.v1.Clarifier", "scruple.v1.Norms"] {
        let answer = health
            .check(tonic_health::pb::HealthCheckRequest {
                service: service.to_owned(),
            })
            .await
            .unwrap()
            .into_inner();
        assert_eq!(
            answer.status(),
            tonic_health::pb::health_check_response::ServingStatus::Serving,
            "{service:?}"
        );
    }
}

#[tokio::test]
async fn rest_keeps_its_own_404_beside_grpc_and_unknown_grpc_methods_are_unimplemented() {
    let app = spawn_app().await;
    let problem = assert_problem(app.get("/v1/unknown").await, StatusCode::NOT_FOUND, None).await;
    assert_eq!(problem["type"], "/problems/no-route");
    // A known gRPC service with an unknown method: tonic answers UNIMPLEMENTED.
    let mut client = tonic::client::Grpc::new(channel(&app).await);
    client.ready().await.unwrap();
    let codec = tonic_prost::ProstCodec::<pb::ListNormsRequest, pb::ListNormsResponse>::default();
    let path = "/scruple.v1.Norms/Nonexistent".parse().unwrap();
    let status = client
        .unary(tonic::Request::new(pb::ListNormsRequest {}), path, codec)
        .await
        .unwrap_err();
    assert_eq!(status.code(), Code::Unimplemented);
    // And the lab scene's REST body works for the REST route still.
    let lab = json!({"directive": {"action": "get", "arguments": [{"type": "mug"}]}, "scene": lab_scene()});
    assert_eq!(app.clarify(&lab).await["decision"], "comply");
}

#[tokio::test]
async fn check_over_grpc_is_the_twin_of_rest() {
    let app = spawn_app().await;
    for norm in paper_demo()["norms"].as_array().unwrap() {
        app.add_norm(norm).await;
    }
    let body = json!({"scene": lab_scene(), "steps": ["get(object4)", "get(object3)"]});
    let rest: Value = app.post("/v1/check", &body).await.json().await.unwrap();
    let scene = clarify_request(&json!({"directive": {}, "scene": lab_scene()})).scene;
    let mut clarifier = ClarifierClient::new(channel(&app).await);
    let grpc = clarifier
        .check(pb::CheckRequest {
            scene,
            steps: vec!["get(object4)".into(), "get(object3)".into()],
            ..Default::default()
        })
        .await
        .expect("check over gRPC")
        .into_inner();
    assert_eq!(grpc.permitted, rest["permitted"].as_bool().unwrap());
    assert_eq!(grpc.utterance, rest["utterance"].as_str().unwrap());
    assert_eq!(grpc.norm_version, rest["norm_version"].as_i64().unwrap());
    let kinds: Vec<Vec<String>> = grpc
        .steps
        .iter()
        .map(|s| s.reasons.iter().map(|r| r.kind.clone()).collect())
        .collect();
    assert_eq!(kinds, vec![vec![], vec!["forbidden_state".to_owned()]]);
    let status = clarifier
        .check(pb::CheckRequest {
            steps: vec!["get(object4)".into()],
            ..Default::default()
        })
        .await
        .unwrap_err();
    assert_eq!(status.code(), Code::InvalidArgument);
    assert_eq!(status.metadata().get("field").unwrap(), "/scene");
}

#[tokio::test]
async fn replace_export_import_and_audit_over_grpc_match_rest() {
    let app = spawn_app().await;
    let mut norms = NormsClient::new(channel(&app).await);
    let created = norms
        .create_norm(norm_request(
            &json!({"kind": "forbidden_state", "state": "did(self,get(object3))"}),
        ))
        .await
        .unwrap()
        .into_inner();
    let rest: Value = app
        .get(&format!("/v1/norms/{}", created.id))
        .await
        .json()
        .await
        .unwrap();
    assert_eq!(rest["revision"].as_i64(), Some(created.revision));

    let replace = |expected: i64| pb::ReplaceNormRequest {
        id: created.id,
        norm: Some(norm_request(
            &json!({"kind": "forbidden_state", "state": "did(self,get(object4))"}),
        )),
        expected_revision: Some(expected),
    };
    let replaced = norms
        .replace_norm(replace(created.revision))
        .await
        .unwrap()
        .into_inner();
    assert!(replaced.revision > created.revision);
    assert_eq!(replaced.state.as_deref(), Some("did(self,get(object4))"));
    let stale = norms.replace_norm(replace(created.revision)).await.unwrap_err();
    assert_eq!(stale.code(), Code::FailedPrecondition);
    let stale_delete = norms
        .delete_norm(pb::DeleteNormRequest {
            id: created.id,
            expected_revision: Some(created.revision),
        })
        .await
        .unwrap_err();
    assert_eq!(stale_delete.code(), Code::FailedPrecondition);

    let exported = norms
        .export_norms(pb::ExportNormsRequest {})
        .await
        .unwrap()
        .into_inner();
    let rest_set: Value = app.get("/v1/norm-set").await.json().await.unwrap();
    assert_eq!(rest_set["version"].as_i64(), Some(exported.version));
    assert_eq!(exported.norms, vec![replaced.clone()]);
    let imported = norms
        .import_norms(pb::ImportNormsRequest {
            norms: vec![pb::ImportedNorm {
                id: Some(7),
                norm: Some(norm_request(&json!({"kind": "forbidden_action", "action": "destroy"}))),
            }],
            expected_version: Some(exported.version),
            clear: false,
            mode: None,
        })
        .await
        .unwrap()
        .into_inner();
    assert_eq!(imported.norms.iter().map(|n| n.id).collect::<Vec<_>>(), vec![7]);
    let stale_import = norms
        .import_norms(pb::ImportNormsRequest {
            norms: vec![],
            expected_version: Some(exported.version),
            clear: true,
            mode: None,
        })
        .await
        .unwrap_err();
    assert_eq!(stale_import.code(), Code::FailedPrecondition);

    let audit = norms
        .list_audit(pb::ListAuditRequest { after: 0, limit: None })
        .await
        .unwrap()
        .into_inner();
    let operations: Vec<&str> = audit.entries.iter().map(|e| e.operation.as_str()).collect();
    assert_eq!(operations, ["create", "replace", "import"]);
    assert_eq!(audit.next_after, audit.entries[2].id);
    assert!(audit.entries.iter().all(|e| e.actor == "anonymous"));
    let bad_limit = norms
        .list_audit(pb::ListAuditRequest {
            after: 0,
            limit: Some(0),
        })
        .await
        .unwrap_err();
    assert_eq!(bad_limit.code(), Code::InvalidArgument);
}

/// proto3 sends a missing list as an empty one: an empty `ImportNorms` must not erase the norms
/// (the hostile pass: `grpcurl -d '{}'` removed every norm, and "Destroy the vase." was obeyed).
#[tokio::test]
async fn an_empty_import_over_grpc_is_refused_unless_it_says_clear() {
    let app = spawn_app().await;
    app.add_norm(&json!({"kind": "forbidden_action", "action": "destroy"}))
        .await;
    let mut norms = NormsClient::new(channel(&app).await);
    let refused = norms.import_norms(pb::ImportNormsRequest::default()).await.unwrap_err();
    assert_eq!(refused.code(), Code::InvalidArgument);
    assert_eq!(refused.metadata().get("field").unwrap(), "/norms");
    let listed: Value = app.get("/v1/norms").await.json().await.unwrap();
    assert_eq!(listed.as_array().unwrap().len(), 1, "nothing was removed");
    let destroy = json!({"directive": {"action": "destroy", "arguments": [{"id": "object3"}]}, "scene": lab_scene()});
    let decided = app.clarify(&destroy).await;
    assert_eq!(decided["decision"], "refuse");

    let both = norms
        .import_norms(pb::ImportNormsRequest {
            norms: vec![pb::ImportedNorm {
                id: None,
                norm: Some(norm_request(&json!({"kind": "forbidden_action", "action": "steal"}))),
            }],
            expected_version: None,
            clear: true,
            mode: None,
        })
        .await
        .unwrap_err();
    assert_eq!(both.code(), Code::InvalidArgument);
    assert_eq!(both.metadata().get("field").unwrap(), "/clear");
    let no_norm = norms
        .import_norms(pb::ImportNormsRequest {
            norms: vec![pb::ImportedNorm {
                id: Some(4),
                norm: None,
            }],
            ..Default::default()
        })
        .await
        .unwrap_err();
    assert_eq!(no_norm.metadata().get("field").unwrap(), "/norms/0/norm");

    let cleared = norms
        .import_norms(pb::ImportNormsRequest {
            clear: true,
            ..Default::default()
        })
        .await
        .unwrap()
        .into_inner();
    assert!(cleared.norms.is_empty());
    let decided = app.clarify(&destroy).await;
    assert_eq!(decided["decision"], "comply", "an explicit clear does clear");
}

/// Other messages whose missing part would silently change norms or decisions are refused too.
#[tokio::test]
async fn missing_messages_that_would_change_norms_or_decisions_are_invalid_arguments() {
    let app = spawn_app().await;
    let channel = channel(&app).await;
    let mut norms = NormsClient::new(channel.clone());
    let replace = norms
        .replace_norm(pb::ReplaceNormRequest {
            id: 1,
            norm: None,
            expected_revision: None,
        })
        .await
        .unwrap_err();
    assert_eq!(replace.code(), Code::InvalidArgument);
    assert_eq!(replace.metadata().get("field").unwrap(), "/norm");
    let mut actions = pb::actions_client::ActionsClient::new(channel.clone());
    let put = actions
        .put_action(pb::PutActionRequest {
            name: "open".to_owned(),
            action: None,
        })
        .await
        .unwrap_err();
    assert_eq!(put.metadata().get("field").unwrap(), "/action");
    let mut request = clarify_request(&get_vase());
    request.scene.as_mut().unwrap().agent.as_mut().unwrap().reach = None;
    let clarify = ClarifierClient::new(channel).clarify(request).await.unwrap_err();
    assert_eq!(clarify.code(), Code::InvalidArgument);
    assert_eq!(clarify.metadata().get("field").unwrap(), "/scene/agent/reach");
}

/// An alternative over gRPC is REST's, field for field, and so is taking it; `alternatives`
/// that is no word (the empty string a client may send for "unset") is INVALID_ARGUMENT naming
/// the option, and a choice of nothing offered is refused naming the answer.
#[tokio::test]
async fn an_alternative_is_offered_alike_over_grpc_and_a_bad_option_is_named() {
    let app = spawn_app().await;
    app.add_norm(&json!({"kind": "forbidden_state", "state": "did(self,get(object3))"}))
        .await;
    let mut clarifier = ClarifierClient::new(channel(&app).await);
    let body = json!({"directive": {"action": "get", "arguments": [{"id": "object3"}]}, "scene": lab_scene(),
                      "options": {"style": "natural"}});
    let rest = app.clarify(&body).await;
    assert_eq!(rest["alternative"], "did(self,get(object4))", "{rest}");
    let grpc = as_rest_json(clarifier.clarify(clarify_request(&body)).await.unwrap().into_inner());
    assert_eq!(grpc, rest);
    // {"choice": "alternative"} (gRPC: `alternative`) takes it, decided afresh, on both.
    let mut taken = body.clone();
    taken["answer"] = json!({"choice": "alternative"});
    let rest = app.clarify(&taken).await;
    assert_eq!(
        (&rest["decision"], &rest["goal"]),
        (&json!("comply"), &json!("did(self,get(object4))")),
        "{rest}"
    );
    let grpc = as_rest_json(clarifier.clarify(clarify_request(&taken)).await.unwrap().into_inner());
    assert_eq!(grpc, rest);
    // With none offered (the diarc style's default) there is nothing to choose: 422 naming the
    // answer; a choice that is neither a position nor the word: 422 naming the choice.
    let mut unasked = taken.clone();
    unasked["options"] = json!({});
    assert_problem(
        app.post("/v1/clarify", &unasked).await,
        StatusCode::UNPROCESSABLE_ENTITY,
        Some("/answer"),
    )
    .await;
    let status = clarifier.clarify(clarify_request(&unasked)).await.unwrap_err();
    assert_eq!(status.metadata().get("field").unwrap(), "/answer");
    for choice in [json!("Alternative"), json!(-1), json!(true)] {
        let mut bad = taken.clone();
        bad["answer"] = json!({"choice": choice});
        assert_problem(
            app.post("/v1/clarify", &bad).await,
            StatusCode::UNPROCESSABLE_ENTITY,
            Some("/answer/choice"),
        )
        .await;
    }
    let mut both = clarify_request(&taken);
    both.answer.as_mut().unwrap().choice = Some(0);
    let status = clarifier.clarify(both).await.unwrap_err();
    assert_eq!(status.code(), Code::InvalidArgument);
    assert_eq!(status.metadata().get("field").unwrap(), "/answer");
    for word in ["", "sometimes"] {
        let mut bad = body.clone();
        bad["options"]["alternatives"] = json!(word);
        let status = clarifier.clarify(clarify_request(&bad)).await.unwrap_err();
        assert_eq!(status.code(), Code::InvalidArgument, "{word:?}");
        assert_eq!(status.metadata().get("field").unwrap(), "/options/alternatives");
        assert_problem(
            app.post("/v1/clarify", &bad).await,
            StatusCode::UNPROCESSABLE_ENTITY,
            Some("/options/alternatives"),
        )
        .await;
    }
}

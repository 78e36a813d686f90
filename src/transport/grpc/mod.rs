//! gRPC over tonic, on the same port as REST: the `Clarifier` and `Norms` services, health and
//! reflection.
//!
//! Owns: proto conversions and gRPC metadata. Must not: validate domain input itself (a proto
//! request becomes the wire body type and passes the same engine checks, so both transports
//! report the same field) or answer a failure except through `Error`.

mod convert;

use tonic::{Request, Response, Status};

use self::convert::word;
use crate::engine::action::ActionInput;
use crate::engine::norms::NormSetMode;
use crate::error::Error;
use crate::transport::auth::Access;
use crate::transport::{AppState, Arrival};
use crate::wire::{AuditEntryDto, CheckBody, CheckDto, ClarifyBody, DecisionDto, NormBody, NormDto, NormSetDto};

/// Generated from `proto/scruple/v1/scruple.proto`.
pub mod pb {
    tonic::include_proto!("scruple.v1");

    /// The encoded descriptor set of `scruple.v1`, served by reflection.
    pub const FILE_DESCRIPTOR_SET: &[u8] = include_bytes!(concat!(env!("OUT_DIR"), "/scruple_descriptor.bin"));
}

use pb::actions_server::{Actions, ActionsServer};
use pb::clarifier_server::{Clarifier, ClarifierServer};
use pb::norms_server::{Norms, NormsServer};

pub struct ClarifierService {
    state: AppState,
}

pub struct NormsService {
    state: AppState,
}

pub struct ActionsService {
    state: AppState,
}

impl From<Error> for Status {
    /// The gRPC twin of the problem body: the code from the same row, the field (when one is
    /// at fault) leading the message and in the `field` metadata entry.
    fn from(error: Error) -> Status {
        let row = error.row();
        error.log(&row);
        let message = match &row.field {
            Some(field) => format!("{field}: {}", row.detail),
            None => row.detail.clone(),
        };
        let mut status = Status::new(tonic::Code::from_i32(row.grpc), message);
        if let Some(seconds) = row.retry_after_s {
            status.metadata_mut().insert("retry-after", seconds.into());
        }
        if let Some(field) = row.field
            && let Ok(value) = field.parse()
        {
            status.metadata_mut().insert("field", value);
        }
        status
    }
}

/// Checks the token sent as metadata `authorization: Bearer TOKEN`; returns its label.
fn authorize<T>(state: &AppState, request: &Request<T>, access: Access) -> Result<std::sync::Arc<str>, Status> {
    let authorization = request.metadata().get("authorization").and_then(|v| v.to_str().ok());
    Ok(state.tokens.authorize(authorization, access)?)
}

fn norm_set(version: i64, norms: &[crate::engine::norms::Norm]) -> pb::NormSet {
    NormSetDto {
        version,
        norms: norms.iter().map(NormDto::from).collect(),
    }
    .into()
}

#[tonic::async_trait]
impl Clarifier for ClarifierService {
    async fn clarify(&self, request: Request<pb::ClarifyRequest>) -> Result<Response<pb::ClarifyResponse>, Status> {
        let arrived = Arrival::of(request.extensions());
        let body = ClarifyBody::try_from(request.into_inner())?;
        let text = body.directive.text.clone();
        let decision = self.state.core.clarify(body.into(), text.as_deref(), arrived).await?;
        let answer = crate::transport::answer(decision, move |decision| {
            pb::ClarifyResponse::from(DecisionDto::new(decision, text))
        })
        .await?;
        Ok(Response::new(answer))
    }

    async fn check(&self, request: Request<pb::CheckRequest>) -> Result<Response<pb::CheckResponse>, Status> {
        let arrived = Arrival::of(request.extensions());
        let body = CheckBody::try_from(request.into_inner())?;
        let check = self.state.core.check(body.into(), arrived).await?;
        Ok(Response::new(CheckDto::from(&check).into()))
    }
}

#[tonic::async_trait]
impl Norms for NormsService {
    async fn create_norm(&self, request: Request<pb::CreateNormRequest>) -> Result<Response<pb::Norm>, Status> {
        let actor = authorize(&self.state, &request, Access::Write)?;
        let body = NormBody::from(request.into_inner());
        let norm = (self.state.core)
            .create_norm(body.id, body.into_input(), &actor)
            .await?;
        Ok(Response::new(NormDto::from(&norm).into()))
    }

    async fn list_norms(
        &self,
        request: Request<pb::ListNormsRequest>,
    ) -> Result<Response<pb::ListNormsResponse>, Status> {
        authorize(&self.state, &request, Access::Read)?;
        let norms = self.state.core.list_norms().await?;
        Ok(Response::new(pb::ListNormsResponse {
            norms: norms.iter().map(|n| NormDto::from(n).into()).collect(),
        }))
    }

    async fn get_norm(&self, request: Request<pb::GetNormRequest>) -> Result<Response<pb::Norm>, Status> {
        authorize(&self.state, &request, Access::Read)?;
        let norm = self.state.core.get_norm(request.into_inner().id).await?;
        Ok(Response::new(NormDto::from(&norm).into()))
    }

    async fn replace_norm(&self, request: Request<pb::ReplaceNormRequest>) -> Result<Response<pb::Norm>, Status> {
        let actor = authorize(&self.state, &request, Access::Write)?;
        let request = request.into_inner();
        let body = NormBody::from(
            request
                .norm
                .ok_or_else(|| Error::invalid("/norm", "missing field `norm`"))?,
        );
        let norm = (self.state.core)
            .replace_norm(
                request.id,
                body.id,
                body.into_input(),
                request.expected_revision,
                &actor,
            )
            .await?;
        Ok(Response::new(NormDto::from(&norm).into()))
    }

    async fn delete_norm(
        &self,
        request: Request<pb::DeleteNormRequest>,
    ) -> Result<Response<pb::DeleteNormResponse>, Status> {
        let actor = authorize(&self.state, &request, Access::Write)?;
        let request = request.into_inner();
        (self.state.core)
            .delete_norm(request.id, request.expected_revision, &actor)
            .await?;
        Ok(Response::new(pb::DeleteNormResponse {}))
    }

    async fn export_norms(&self, request: Request<pb::ExportNormsRequest>) -> Result<Response<pb::NormSet>, Status> {
        authorize(&self.state, &request, Access::Read)?;
        let (version, norms) = self.state.core.export_norms().await?;
        Ok(Response::new(norm_set(version, &norms)))
    }

    async fn import_norms(&self, request: Request<pb::ImportNormsRequest>) -> Result<Response<pb::NormSet>, Status> {
        let actor = authorize(&self.state, &request, Access::Write)?;
        let request = request.into_inner();
        let mode = word::<NormSetMode>("/mode", request.mode)?.unwrap_or_default();
        if mode == NormSetMode::Merge && request.clear {
            return Err(
                Error::invalid("/clear", "`clear` empties the set: a merge keeps what it does not name").into(),
            );
        }
        // REST refuses a body without `norms`; proto3 sends no list as an empty one, so only an
        // explicit `clear` may empty the norm set (a merge of nothing empties nothing).
        if request.norms.is_empty() && !request.clear && mode == NormSetMode::Replace {
            return Err(Error::invalid(
                "/norms",
                "an import with no norms would remove every norm: set `clear: true` to do that",
            )
            .into());
        }
        if !request.norms.is_empty() && request.clear {
            return Err(Error::invalid("/clear", "`clear` empties the set: send it with no norms").into());
        }
        let inputs = (request.norms.into_iter())
            .enumerate()
            .map(|(i, n)| {
                let norm = n
                    .norm
                    .ok_or_else(|| Error::invalid(format!("/norms/{i}/norm"), "missing field `norm`"))?;
                Ok((n.id, NormBody::from(norm).into_input()))
            })
            .collect::<Result<_, Error>>()?;
        let (version, norms) = (self.state.core)
            .import_norms(inputs, mode, request.expected_version, &actor)
            .await?;
        Ok(Response::new(norm_set(version, &norms)))
    }

    async fn list_audit(
        &self,
        request: Request<pb::ListAuditRequest>,
    ) -> Result<Response<pb::ListAuditResponse>, Status> {
        authorize(&self.state, &request, Access::Read)?;
        let request = request.into_inner();
        let page = self.state.core.audit(request.after, request.limit).await?;
        Ok(Response::new(pb::ListAuditResponse {
            entries: page
                .entries
                .into_iter()
                .map(|e| AuditEntryDto::from(e).into())
                .collect(),
            next_after: page.next_after,
        }))
    }
}

#[tonic::async_trait]
impl Actions for ActionsService {
    async fn list_actions(
        &self,
        request: Request<pb::ListActionsRequest>,
    ) -> Result<Response<pb::ListActionsResponse>, Status> {
        authorize(&self.state, &request, Access::Read)?;
        let actions = self.state.core.list_actions().await?;
        Ok(Response::new(pb::ListActionsResponse {
            actions: actions.into_iter().map(Into::into).collect(),
        }))
    }

    async fn get_action(&self, request: Request<pb::GetActionRequest>) -> Result<Response<pb::Action>, Status> {
        authorize(&self.state, &request, Access::Read)?;
        let action = self.state.core.get_action(&request.into_inner().name).await?;
        Ok(Response::new(action.into()))
    }

    async fn put_action(
        &self,
        request: Request<pb::PutActionRequest>,
    ) -> Result<Response<pb::PutActionResponse>, Status> {
        let actor = authorize(&self.state, &request, Access::Write)?;
        let request = request.into_inner();
        let body = ActionInput::from(
            request
                .action
                .ok_or_else(|| Error::invalid("/action", "missing field `action`"))?,
        );
        let (stored, created) = self.state.core.put_action(&request.name, body, &actor).await?;
        Ok(Response::new(pb::PutActionResponse {
            action: Some(stored.into()),
            created,
        }))
    }

    async fn delete_action(
        &self,
        request: Request<pb::DeleteActionRequest>,
    ) -> Result<Response<pb::DeleteActionResponse>, Status> {
        let actor = authorize(&self.state, &request, Access::Write)?;
        self.state
            .core
            .delete_action(&request.into_inner().name, &actor)
            .await?;
        Ok(Response::new(pb::DeleteActionResponse {}))
    }
}

/// The encoded `FileDescriptorSet` of every gRPC service [`router`] serves: the observing layer
/// takes its method names and its routes' templates from these.
pub const SERVED_DESCRIPTOR_SETS: [&[u8]; 4] = [
    pb::FILE_DESCRIPTOR_SET,
    tonic_health::pb::FILE_DESCRIPTOR_SET,
    tonic_reflection::pb::v1::FILE_DESCRIPTOR_SET,
    tonic_reflection::pb::v1alpha::FILE_DESCRIPTOR_SET,
];

/// The gRPC services as an axum router: scruple.v1, `grpc.health.v1.Health` (SERVING: the store
/// is open and migrated before this is built) and reflection, both v1 and v1alpha (older grpcurl
/// speaks only v1alpha).
pub async fn router(state: AppState) -> Result<axum::Router, Error> {
    // The REST body limit holds for gRPC messages too (RESOURCE_EXHAUSTED above it).
    let limit = state.max_body_bytes;
    let (health_reporter, health) = tonic_health::server::health_reporter();
    state.core.probe(std::time::Duration::ZERO).await;
    report_health(&health_reporter, state.core.readiness().is_ok()).await;
    tokio::spawn(follow_readiness(
        std::sync::Arc::downgrade(&state.core),
        health_reporter,
    ));
    let reflection = || {
        tonic_reflection::server::Builder::configure()
            .register_encoded_file_descriptor_set(pb::FILE_DESCRIPTOR_SET)
            .register_encoded_file_descriptor_set(tonic_health::pb::FILE_DESCRIPTOR_SET)
    };
    let reflection_v1 = reflection()
        .build_v1()
        .map_err(|e| Error::Internal(format!("reflection: {e}")))?;
    let reflection_v1alpha = reflection()
        .build_v1alpha()
        .map_err(|e| Error::Internal(format!("reflection: {e}")))?;
    Ok(tonic::service::Routes::new(health)
        .add_service(reflection_v1)
        .add_service(reflection_v1alpha)
        .add_service(ClarifierServer::new(ClarifierService { state: state.clone() }).max_decoding_message_size(limit))
        .add_service(NormsServer::new(NormsService { state: state.clone() }).max_decoding_message_size(limit))
        .add_service(ActionsServer::new(ActionsService { state }).max_decoding_message_size(limit))
        .into_axum_router()
        // A plain map of the answer: no boxed copy of the services below, no boxed future.
        .layer(tower::util::MapResponseLayer::new(request_faults as fn(_) -> _)))
}

async fn report_health(reporter: &tonic_health::server::HealthReporter, ready: bool) {
    let status = if ready {
        tonic_health::ServingStatus::Serving
    } else {
        tonic_health::ServingStatus::NotServing
    };
    reporter.set_service_status("", status).await;
    reporter
        .set_service_status(
            <ClarifierServer<ClarifierService> as tonic::server::NamedService>::NAME,
            status,
        )
        .await;
    reporter
        .set_service_status(<NormsServer<NormsService> as tonic::server::NamedService>::NAME, status)
        .await;
    reporter
        .set_service_status(
            <ActionsServer<ActionsService> as tonic::server::NamedService>::NAME,
            status,
        )
        .await;
}

/// Keeps readiness at most a second old when no request reads the knowledge, and gRPC health
/// saying what `/healthz` says. Ends when the service (its core) is gone.
async fn follow_readiness(core: std::sync::Weak<crate::core::Core>, reporter: tonic_health::server::HealthReporter) {
    let mut reported = None;
    loop {
        tokio::time::sleep(std::time::Duration::from_millis(250)).await;
        let Some(core) = core.upgrade() else { return };
        core.probe(std::time::Duration::from_secs(1)).await;
        let ready = core.readiness().is_ok();
        drop(core);
        if reported != Some(ready) {
            report_health(&reporter, ready).await;
            reported = Some(ready);
        }
    }
}

/// tonic answers a request it cannot decode with INTERNAL (a malformed message, no message, a
/// bad compression flag) and one over the size limit with OUT_OF_RANGE. Those are the caller's
/// faults: they become INVALID_ARGUMENT and RESOURCE_EXHAUSTED, as REST's 400 and 413 are. Only
/// tonic's own decoding messages are matched, so the service's INTERNAL stays INTERNAL.
fn request_faults(response: axum::response::Response) -> axum::response::Response {
    let Some(status) = Status::from_header_map(response.headers()) else {
        return response;
    };
    let message = status.message();
    let code = match status.code() {
        tonic::Code::Internal
            if [
                "failed to decode Protobuf message",
                "Missing request message",
                "protocol error: received message with",
                "Unexpected EOF decoding stream",
                "Error decompressing",
            ]
            .iter()
            .any(|p| message.starts_with(p)) =>
        {
            tonic::Code::InvalidArgument
        }
        tonic::Code::OutOfRange if message.starts_with("Error, decoded message length too large") => {
            tonic::Code::ResourceExhausted
        }
        _ => return response,
    };
    Status::new(code, message.to_owned()).into_http()
}

//! gRPC over tonic, on the same port as REST: the `Clarifier` and `Norms` services, health and
//! reflection.
//!
//! Owns: proto conversions and gRPC metadata. Must not: validate domain input itself (a proto
//! request becomes the REST body type and passes the same checks, so both transports report the
//! same field) or answer a failure except through `Error`.

mod convert;

use tonic::{Request, Response, Status};

use crate::api::{CheckBody, CheckDto, CheckInput, ClarifyBody, ClarifyInput, DecisionDto, NormBody, NormDto};
use crate::engine::action::ActionInput;
use crate::error::Error;
use crate::transport::AppState;

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

/// Checks the admin token sent as metadata `authorization: Bearer TOKEN`.
fn authorize<T>(state: &AppState, request: &Request<T>) -> Result<(), Status> {
    let authorization = request.metadata().get("authorization").and_then(|v| v.to_str().ok());
    Ok(state.authorize_write(authorization)?)
}

#[tonic::async_trait]
impl Clarifier for ClarifierService {
    async fn clarify(&self, request: Request<pb::ClarifyRequest>) -> Result<Response<pb::ClarifyResponse>, Status> {
        let body = ClarifyBody::try_from(request.into_inner())?;
        let mut input = ClarifyInput::try_from(body)?;
        let text = input.text.take();
        let decision = self.state.core.clarify(input).await?;
        Ok(Response::new(DecisionDto::new(&decision, text).into()))
    }

    async fn check(&self, request: Request<pb::CheckRequest>) -> Result<Response<pb::CheckResponse>, Status> {
        let input = CheckInput::try_from(CheckBody::try_from(request.into_inner())?)?;
        let check = self.state.core.check(input).await?;
        Ok(Response::new(CheckDto::from(&check).into()))
    }
}

#[tonic::async_trait]
impl Norms for NormsService {
    async fn create_norm(&self, request: Request<pb::CreateNormRequest>) -> Result<Response<pb::Norm>, Status> {
        authorize(&self.state, &request)?;
        let body = NormBody::from(request.into_inner());
        let norm = self.state.core.create_norm(body.into_input()).await?;
        Ok(Response::new(NormDto::from(&norm).into()))
    }

    async fn list_norms(&self, _: Request<pb::ListNormsRequest>) -> Result<Response<pb::ListNormsResponse>, Status> {
        let norms = self.state.core.list_norms().await?;
        Ok(Response::new(pb::ListNormsResponse {
            norms: norms.iter().map(|n| NormDto::from(n).into()).collect(),
        }))
    }

    async fn get_norm(&self, request: Request<pb::GetNormRequest>) -> Result<Response<pb::Norm>, Status> {
        let norm = self.state.core.get_norm(request.into_inner().id).await?;
        Ok(Response::new(NormDto::from(&norm).into()))
    }

    async fn delete_norm(
        &self,
        request: Request<pb::DeleteNormRequest>,
    ) -> Result<Response<pb::DeleteNormResponse>, Status> {
        authorize(&self.state, &request)?;
        self.state.core.delete_norm(request.into_inner().id).await?;
        Ok(Response::new(pb::DeleteNormResponse {}))
    }
}

#[tonic::async_trait]
impl Actions for ActionsService {
    async fn list_actions(
        &self,
        _: Request<pb::ListActionsRequest>,
    ) -> Result<Response<pb::ListActionsResponse>, Status> {
        let actions = self.state.core.list_actions().await?;
        Ok(Response::new(pb::ListActionsResponse {
            actions: actions.into_iter().map(Into::into).collect(),
        }))
    }

    async fn get_action(&self, request: Request<pb::GetActionRequest>) -> Result<Response<pb::Action>, Status> {
        let action = self.state.core.get_action(&request.into_inner().name).await?;
        Ok(Response::new(action.into()))
    }

    async fn put_action(
        &self,
        request: Request<pb::PutActionRequest>,
    ) -> Result<Response<pb::PutActionResponse>, Status> {
        authorize(&self.state, &request)?;
        let request = request.into_inner();
        let body = ActionInput::from(request.action.unwrap_or_default());
        let (stored, created) = self.state.core.put_action(&request.name, body).await?;
        Ok(Response::new(pb::PutActionResponse {
            action: Some(stored.into()),
            created,
        }))
    }

    async fn delete_action(
        &self,
        request: Request<pb::DeleteActionRequest>,
    ) -> Result<Response<pb::DeleteActionResponse>, Status> {
        authorize(&self.state, &request)?;
        self.state.core.delete_action(&request.into_inner().name).await?;
        Ok(Response::new(pb::DeleteActionResponse {}))
    }
}

/// The gRPC services as an axum router: scruple.v1, `grpc.health.v1.Health` (SERVING: the store
/// is open and migrated before this is built) and reflection, both v1 and v1alpha (older grpcurl
/// speaks only v1alpha).
pub async fn router(state: AppState) -> Result<axum::Router, Error> {
    let (health_reporter, health) = tonic_health::server::health_reporter();
    health_reporter.set_serving::<ClarifierServer<ClarifierService>>().await;
    health_reporter.set_serving::<NormsServer<NormsService>>().await;
    health_reporter.set_serving::<ActionsServer<ActionsService>>().await;
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
        .add_service(ClarifierServer::new(ClarifierService { state: state.clone() }))
        .add_service(NormsServer::new(NormsService { state: state.clone() }))
        .add_service(ActionsServer::new(ActionsService { state }))
        .into_axum_router())
}

//! REST over axum: routes, body parsing, the admin-token check.
//!
//! Owns: HTTP concerns only. Must not: validate domain input (that is `api`), decide anything
//! (that is `core`), or answer any failure except through `Error` (or, for a body that did not
//! arrive in time, the connection layer's 408 problem).

use axum::extract::{DefaultBodyLimit, FromRequest, FromRequestParts, Path, Request, State};
use axum::http::request::Parts;
use axum::http::{HeaderValue, StatusCode, header};
use axum::response::{IntoResponse, Response};
use axum::{Extension, Json, Router};
use bytes::Bytes;
use serde::de::DeserializeOwned;
use tower_http::catch_panic::CatchPanicLayer;
use utoipa::OpenApi;
use utoipa_axum::router::OpenApiRouter;
use utoipa_axum::routes;

use crate::engine::action::ActionInput;
use crate::error::{Error, PROBLEM_JSON, Problem};
use crate::transport::auth::Access;
use crate::transport::conn::{self, problem::Protocol};
use crate::transport::{AppState, Arrival};
use crate::wire::{
    ActionSchema, AuditPageDto, CheckBody, CheckDto, ClarifyBody, DecisionDto, NormBody, NormDto, NormSetBody,
    NormSetDto, NormSetImportSchema, parse_json,
};

mod coding;
mod doc;
mod playground;
mod service;

/// Every REST route, each registered with its OpenAPI operation: a route cannot be added here
/// without documenting it, and `tests/api/openapi.rs` fails if anything is routed another way.
fn routes() -> OpenApiRouter<AppState> {
    OpenApiRouter::with_openapi(doc::ApiDoc::openapi())
        .routes(routes!(service::healthz))
        .routes(routes!(service::livez))
        .routes(routes!(service::readyz))
        .routes(routes!(service::version))
        .routes(routes!(service::openapi_json))
        .routes(routes!(service::metrics))
        .routes(routes!(list_norms, create_norm))
        .routes(routes!(get_norm, replace_norm, delete_norm))
        .routes(routes!(export_norms, import_norms))
        .routes(routes!(audit))
        .routes(routes!(clarify))
        .routes(routes!(check))
        .routes(routes!(list_actions))
        .routes(routes!(get_action, put_action, delete_action))
        .routes(routes!(playground::index))
        .routes(routes!(playground::script))
        .routes(routes!(playground::style))
}

/// The OpenAPI 3.1 document of the REST API, as `openapi/openapi.json` holds it.
pub fn openapi() -> utoipa::openapi::OpenApi {
    routes().into_openapi()
}

/// The REST routes with their layers (body limit, panic guard). Fallbacks are set on the
/// merged router in `app`, after gRPC's routes join.
pub fn router(state: AppState) -> Router {
    let limit = state.max_body_bytes;
    let (router, _) = routes().split_for_parts();
    // One `layer` call, so one level: each level is a boxed service that every request clones
    // and a boxed future (see `app::one_port`). The panic guard is the outer of the two.
    let layers = tower::ServiceBuilder::new()
        .layer(CatchPanicLayer::custom(|_: Box<dyn std::any::Any + Send>| {
            Error::Internal("a handler panicked".to_owned()).into_response()
        }))
        .layer(DefaultBodyLimit::max(limit));
    router.layer(layers).with_state(state)
}

impl IntoResponse for Error {
    /// The problem+json answer of a failure, from its row in the one table.
    fn into_response(self) -> Response {
        let row = self.row();
        self.log(&row);
        let status = StatusCode::from_u16(row.http).unwrap_or(StatusCode::INTERNAL_SERVER_ERROR);
        let retry_after_s = row.retry_after_s;
        let mut response = (status, Json(self.problem())).into_response();
        let headers = response.headers_mut();
        headers.insert(header::CONTENT_TYPE, HeaderValue::from_static(PROBLEM_JSON));
        if matches!(self, Error::Unauthenticated) {
            headers.insert(header::WWW_AUTHENTICATE, HeaderValue::from_static("Bearer"));
        }
        if let Some(seconds) = retry_after_s {
            headers.insert(header::RETRY_AFTER, HeaderValue::from(seconds));
        }
        response
    }
}

/// A JSON body: not JSON → 400, wrong shape → 422 naming the field, too large (as sent or once
/// decoded) → 413, not JSON or in an unknown coding → 415, not arrived in time → 408.
pub struct JsonBody<T>(pub T);

impl<T: DeserializeOwned> FromRequest<AppState> for JsonBody<T> {
    type Rejection = Response;

    async fn from_request(req: Request, state: &AppState) -> Result<Self, Response> {
        if let Some(content_type) = req.headers().get(header::CONTENT_TYPE) {
            let text = content_type.to_str().unwrap_or_default().to_ascii_lowercase();
            let essence = text.split(';').next().unwrap_or_default().trim();
            if essence != "application/json" && !essence.ends_with("+json") {
                return Err(Error::UnsupportedMediaType {
                    detail: format!("send the body as application/json, not `{essence}`"),
                }
                .into_response());
            }
        }
        let coding = coding::of(req.headers()).map_err(IntoResponse::into_response)?;
        let version = req.version();
        let bytes = Bytes::from_request(req, state).await.map_err(|rejection| {
            if let Some(timeout) = conn::body::timed_out(&rejection) {
                return Protocol::RequestTimeout.response(timeout.to_string(), version);
            }
            if rejection.status() == StatusCode::PAYLOAD_TOO_LARGE {
                Error::PayloadTooLarge {
                    limit: state.max_body_bytes,
                }
                .into_response()
            } else {
                Error::MalformedBody {
                    detail: rejection.body_text(),
                }
                .into_response()
            }
        })?;
        let bytes = coding::decode(coding, bytes, state.max_body_bytes).map_err(IntoResponse::into_response)?;
        parse_json(&bytes).map(JsonBody).map_err(IntoResponse::into_response)
    }
}

/// A caller allowed to change norms and verbs: the label of its token (see `auth::Tokens`).
pub struct Writer(pub std::sync::Arc<str>);

impl FromRequestParts<AppState> for Writer {
    type Rejection = Error;

    async fn from_request_parts(parts: &mut Parts, state: &AppState) -> Result<Self, Error> {
        let authorization = parts.headers.get(header::AUTHORIZATION).and_then(|v| v.to_str().ok());
        state.tokens.authorize(authorization, Access::Write).map(Writer)
    }
}

/// A caller allowed to read the curated state (always, unless reader tokens are configured).
pub struct Reader;

impl FromRequestParts<AppState> for Reader {
    type Rejection = Error;

    async fn from_request_parts(parts: &mut Parts, state: &AppState) -> Result<Self, Error> {
        let authorization = parts.headers.get(header::AUTHORIZATION).and_then(|v| v.to_str().ok());
        state.tokens.authorize(authorization, Access::Read).map(|_| Reader)
    }
}

/// `If-Match` (RFC 9110 §13.1.1): absent or `*` asks for no precondition; otherwise a list of
/// entity tags, any of which may match. The comparison is strong, so a weak tag (`W/"12"`)
/// never matches a write, nor does anything but a tag as the API gives them (`"12"`): such a
/// write is refused as stale rather than done unconditionally.
pub enum IfMatch {
    Any,
    /// The revisions of the strong tags listed, and the header as sent (for the 412's words).
    Tags(Vec<i64>, String),
}

impl FromRequestParts<AppState> for IfMatch {
    type Rejection = Error;

    async fn from_request_parts(parts: &mut Parts, _: &AppState) -> Result<Self, Error> {
        let Some(value) = parts.headers.get(header::IF_MATCH) else {
            return Ok(IfMatch::Any);
        };
        let text = value.to_str().unwrap_or_default().trim();
        if text == "*" {
            return Ok(IfMatch::Any);
        }
        let revisions = text
            .split(',')
            .filter_map(|tag| {
                tag.trim()
                    .strip_prefix('"')?
                    .strip_suffix('"')?
                    .parse::<i64>()
                    .ok()
                    .filter(|r| *r >= 0)
            })
            .collect();
        Ok(IfMatch::Tags(revisions, text.chars().take(200).collect()))
    }
}

impl IfMatch {
    /// The revision a write is made conditional on: none for `*`; the one tag listed; with
    /// several, the current revision when it is among them (the store still checks it has not
    /// moved since). `current` is read only then; `what` names the thing for a 412.
    async fn expected(
        self,
        what: impl FnOnce() -> String,
        current: impl Future<Output = Result<i64, Error>>,
    ) -> Result<Option<i64>, Error> {
        let (revisions, sent) = match self {
            IfMatch::Any => return Ok(None),
            IfMatch::Tags(revisions, _) if revisions.len() == 1 => return Ok(Some(revisions[0])),
            IfMatch::Tags(revisions, sent) => (revisions, sent),
        };
        let current = current.await?;
        if revisions.contains(&current) {
            return Ok(Some(current));
        }
        let expected = if revisions.is_empty() {
            format!("{sent} (no strong entity tag: a weak one never matches a write)")
        } else {
            format!("any of {sent}")
        };
        Err(Error::Stale {
            what: what(),
            expected,
            current,
        })
    }
}

/// `ETag: "N"` for a norm's revision or the norm set's version.
fn with_etag(mut response: Response, revision: i64) -> Response {
    if let Ok(value) = HeaderValue::from_str(&format!("\"{revision}\"")) {
        response.headers_mut().insert(header::ETAG, value);
    }
    response
}

/// The revision a conditional write on norm `id` expects.
async fn norm_revision(app: &AppState, id: i64, if_match: IfMatch) -> Result<Option<i64>, Error> {
    let current = async { Ok(app.core.get_norm(id).await?.revision) };
    if_match.expected(|| format!("norm {id}"), current).await
}

/// A norm id from the path; anything but an integer names no norm.
fn norm_id(text: &str) -> Result<i64, Error> {
    text.parse().map_err(|_| Error::NotFound {
        what: format!("norm `{text}`"),
    })
}

#[utoipa::path(get, path = "/v1/norms", tag = "norms",
    summary = "Every norm, by ascending id",
    security((), ("token" = [])),
    responses(
        (status = 200, description = "The norms", body = Vec<NormDto>),
        doc::problems::Store,
        doc::problems::ReadToken,
    ))]
async fn list_norms(State(app): State<AppState>, _: Reader) -> Result<Json<Vec<NormDto>>, Error> {
    let norms = app.core.list_norms().await?;
    Ok(Json(norms.iter().map(NormDto::from).collect()))
}

#[utoipa::path(post, path = "/v1/norms", tag = "norms",
    summary = "Add a norm; nothing is stored unless every field is valid",
    request_body(content = NormBody, example = json!({"kind": "forbidden_state", "state": "did(self,get(object3))", "note": "the fragile vase may not be got"})),
    security((), ("token" = [])),
    responses(
        (status = 201, description = "Stored, with its id; `Location` names it, `ETag` is its revision", body = NormDto,
         headers(("location" = String, description = "/v1/norms/{id}"), ("etag" = String, description = "The revision, quoted")),
         example = json!({"id": 2, "revision": 2, "kind": "forbidden_state", "state": "did(self,get(object3))", "when": [], "severity": 3, "note": "the fragile vase may not be got"})),
        (status = 422, description = "A field is wrong; `field` points at it", body = Problem, content_type = PROBLEM_JSON,
         example = json!({"type": "/problems/invalid-field", "title": "Invalid field", "status": 422, "detail": "6 is out of range 1..5", "field": "/severity"})),
        doc::problems::Store,
        doc::problems::JsonBody,
        doc::problems::WriteToken,
    ))]
async fn create_norm(
    State(app): State<AppState>,
    Writer(actor): Writer,
    JsonBody(body): JsonBody<NormBody>,
) -> Result<Response, Error> {
    let norm = app.core.create_norm(body.id, body.into_input(), &actor).await?;
    let mut response = (StatusCode::CREATED, Json(NormDto::from(&norm))).into_response();
    if let Ok(location) = HeaderValue::from_str(&format!("/v1/norms/{}", norm.id)) {
        response.headers_mut().insert(header::LOCATION, location);
    }
    Ok(with_etag(response, norm.revision))
}

#[utoipa::path(get, path = "/v1/norms/{id}", tag = "norms",
    summary = "One norm, with its revision as `ETag`",
    params(("id" = i64, Path, description = "The norm's id")),
    security((), ("token" = [])),
    responses(
        (status = 200, description = "The norm", body = NormDto, headers(("etag" = String, description = "The revision, quoted"))),
        doc::problems::NoNorm,
        doc::problems::Store,
        doc::problems::ReadToken,
    ))]
async fn get_norm(State(app): State<AppState>, _: Reader, Path(id): Path<String>) -> Result<Response, Error> {
    let norm = app.core.get_norm(norm_id(&id)?).await?;
    Ok(with_etag(Json(NormDto::from(&norm)).into_response(), norm.revision))
}

#[utoipa::path(put, path = "/v1/norms/{id}", tag = "norms",
    summary = "Replace a norm (its id stays); with `If-Match`, only if nobody changed it since",
    description = "Send the `ETag` from GET (or the norm's `revision`, quoted) in `If-Match`: if the norm has changed since, nothing is written and the answer is 412. Without `If-Match` (or with `*`) the norm is replaced whatever its revision.",
    params(
        ("id" = i64, Path, description = "The norm's id"),
        ("if-match" = Option<String>, Header, description = "The revision expected, as an ETag: `\"12\"`"),
    ),
    request_body(content = NormBody, example = json!({"kind": "forbidden_state", "state": "did(self,get(object3))", "severity": 4})),
    security((), ("token" = [])),
    responses(
        (status = 200, description = "Replaced; the norm as stored, its new revision in `ETag`", body = NormDto,
         headers(("etag" = String, description = "The new revision, quoted"))),
        doc::problems::NoNorm,
        doc::problems::Changed,
        (status = 422, description = "A field is wrong; `field` points at it", body = Problem, content_type = PROBLEM_JSON),
        doc::problems::Store,
        doc::problems::JsonBody,
        doc::problems::WriteToken,
    ))]
async fn replace_norm(
    State(app): State<AppState>,
    Writer(actor): Writer,
    if_match: IfMatch,
    Path(id): Path<String>,
    JsonBody(body): JsonBody<NormBody>,
) -> Result<Response, Error> {
    let id = norm_id(&id)?;
    let expected = norm_revision(&app, id, if_match).await?;
    let norm = app
        .core
        .replace_norm(id, body.id, body.into_input(), expected, &actor)
        .await?;
    Ok(with_etag(Json(NormDto::from(&norm)).into_response(), norm.revision))
}

#[utoipa::path(delete, path = "/v1/norms/{id}", tag = "norms",
    summary = "Remove a norm; with `If-Match`, only if nobody changed it since",
    params(
        ("id" = i64, Path, description = "The norm's id"),
        ("if-match" = Option<String>, Header, description = "The revision expected, as an ETag: `\"12\"`"),
    ),
    security((), ("token" = [])),
    responses(
        (status = 204, description = "Removed"),
        doc::problems::NoNorm,
        doc::problems::Changed,
        doc::problems::Store,
        doc::problems::WriteToken,
    ))]
async fn delete_norm(
    State(app): State<AppState>,
    Writer(actor): Writer,
    if_match: IfMatch,
    Path(id): Path<String>,
) -> Result<StatusCode, Error> {
    let id = norm_id(&id)?;
    let expected = norm_revision(&app, id, if_match).await?;
    app.core.delete_norm(id, expected, &actor).await?;
    Ok(StatusCode::NO_CONTENT)
}

#[utoipa::path(get, path = "/v1/norm-set", tag = "norms",
    summary = "Export the whole norm set, for backups and review",
    security((), ("token" = [])),
    responses(
        (status = 200, description = "Every norm and the version they make up (also the `ETag`)", body = NormSetDto,
         headers(("etag" = String, description = "The norm-set version, quoted"))),
        doc::problems::Store,
        doc::problems::ReadToken,
    ))]
async fn export_norms(State(app): State<AppState>, _: Reader) -> Result<Response, Error> {
    let (version, norms) = app.core.export_norms().await?;
    let set = NormSetDto {
        version,
        norms: norms.iter().map(NormDto::from).collect(),
    };
    Ok(with_etag(Json(set).into_response(), version))
}

#[utoipa::path(put, path = "/v1/norm-set", tag = "norms",
    summary = "Import a norm set in one transaction: as the whole set, or merged over the stored one",
    description = "Takes what GET /v1/norm-set gives, or a plain list of norms (the offline CLI's norms file), taken as the set's `norms`. Every norm is validated before anything changes; ids given are kept, norms without one get fresh ids. `mode: \"replace\"` (the default; a plain list always replaces) makes these norms the whole set; `mode: \"merge\"` replaces only the norms named by id, adds the rest, and keeps every other stored norm and its revision (merging no norms changes nothing). With `If-Match` (the set's ETag) the import happens only if the set has not changed since.",
    params(("if-match" = Option<String>, Header, description = "The norm-set version expected, as an ETag")),
    request_body(content = NormSetImportSchema, example = json!({"norms": [{"id": 1, "kind": "forbidden_state", "state": "did(self,get(object3))"}]})),
    security((), ("token" = [])),
    responses(
        (status = 200, description = "Imported; the set as stored, its version in `ETag`", body = NormSetDto,
         headers(("etag" = String, description = "The new norm-set version, quoted"))),
        doc::problems::Changed,
        (status = 422, description = "A norm is wrong; `field` points at it (`/norms/3/severity`, or `/3/severity` in a list); or the body is neither a norm set nor a list of norms", body = Problem, content_type = PROBLEM_JSON),
        doc::problems::Store,
        doc::problems::JsonBody,
        doc::problems::WriteToken,
    ))]
async fn import_norms(
    State(app): State<AppState>,
    Writer(actor): Writer,
    if_match: IfMatch,
    JsonBody(body): JsonBody<NormSetBody>,
) -> Result<Response, Error> {
    let current = async { Ok(app.core.export_norms().await?.0) };
    let expected = if_match.expected(|| "the norm set".to_owned(), current).await?;
    let inputs = body.norms.into_iter().map(|n| (n.id, n.into_input())).collect();
    let imported = app.core.import_norms(inputs, body.mode, expected, &actor).await;
    // Core points into a set's `norms`; a list sent bare is pointed into as it was sent.
    let (version, norms) = imported.map_err(|e| match e {
        Error::Invalid { field, detail } if body.listed => Error::Invalid {
            field: field
                .strip_prefix("/norms")
                .map_or_else(|| field.clone(), str::to_owned),
            detail,
        },
        other => other,
    })?;
    let set = NormSetDto {
        version,
        norms: norms.iter().map(NormDto::from).collect(),
    };
    Ok(with_etag(Json(set).into_response(), version))
}

/// `?after=ID&limit=N` for the audit trail.
#[derive(serde::Deserialize, utoipa::IntoParams)]
#[into_params(parameter_in = Query)]
struct AuditQuery {
    /// Entries with ids above this one (default 0: from the start).
    after: Option<i64>,
    /// At most this many entries, 1..=1000 (default 100).
    limit: Option<i64>,
}

impl AuditQuery {
    /// The members, percent-decoded. Each is a 422 naming it (`/after`, `/limit`, `/actor`)
    /// when it is not an integer, is given twice, or is not one the trail takes: a filter the
    /// service does not have (`?actor=alice`) must not be answered as if it had applied it.
    fn parse(uri: &axum::http::Uri) -> Result<AuditQuery, Error> {
        let axum::extract::Query(pairs) = axum::extract::Query::<Vec<(String, String)>>::try_from_uri(uri)
            .map_err(|rejection| Error::invalid("", rejection.body_text()))?;
        let mut parsed = AuditQuery {
            after: None,
            limit: None,
        };
        for (key, value) in pairs {
            let field = format!("/{}", crate::wire::pointer_segment(&key));
            let shown = crate::engine::input::escape_unseen(&key);
            let slot = match key.as_str() {
                "after" => &mut parsed.after,
                "limit" => &mut parsed.limit,
                _ => {
                    return Err(Error::invalid(
                        field,
                        format!("`{shown}` is not a member of this query: the audit trail takes `after` and `limit`"),
                    ));
                }
            };
            if slot.is_some() {
                return Err(Error::invalid(field, format!("`{shown}` is given twice")));
            }
            let number = value
                .parse::<i64>()
                .map_err(|_| Error::invalid(field, format!("`{shown}` must be an integer")))?;
            *slot = Some(number);
        }
        Ok(parsed)
    }
}

#[utoipa::path(get, path = "/v1/audit", tag = "norms",
    summary = "The audit trail: every change to norms and verbs, oldest first",
    params(AuditQuery),
    security((), ("token" = [])),
    responses(
        (status = 200, description = "A page of entries", body = AuditPageDto),
        (status = 422, description = "`after` or `limit` is not an integer, is given twice, or `limit` is out of range; or the query has a member the trail does not take (`actor`): `field` names it", body = Problem, content_type = PROBLEM_JSON),
        doc::problems::Store,
        doc::problems::ReadToken,
    ))]
async fn audit(State(app): State<AppState>, _: Reader, request: Request) -> Result<Json<AuditPageDto>, Error> {
    let query = AuditQuery::parse(request.uri())?;
    let after = query.after.unwrap_or(0);
    let page = app.core.audit(after, query.limit).await?;
    let entries = page.entries.into_iter().map(Into::into).collect();
    Ok(Json(AuditPageDto {
        entries,
        next_after: page.next_after,
    }))
}

#[utoipa::path(post, path = "/v1/clarify", tag = "clarify",
    summary = "Decide what to say about a directive that may be ambiguous",
    description = "Simulates every reading of the directive against the norms in force and the robot's abilities, then complies, refuses, asks about the permissible readings only, assumes (or confirms) the one permissible reading, explains why none can be done, or says a reference is unresolved.",
    request_body(content = ClarifyBody, example = json!(doc::vase_request())),
    responses(
        (status = 200, description = "The decision, its words and every reading considered", body = DecisionDto, example = json!(doc::vase_response())),
        (status = 422, description = "A field is wrong; `field` points at it", body = Problem, content_type = PROBLEM_JSON,
         example = json!({"type": "/problems/invalid-field", "title": "Invalid field", "status": 422, "detail": "no object `object9` in the scene", "field": "/directive/arguments/0/id"})),
        doc::problems::FailClosed,
        doc::problems::JsonBody,
    ))]
async fn clarify(
    State(app): State<AppState>,
    arrival: Option<Extension<Arrival>>,
    JsonBody(body): JsonBody<ClarifyBody>,
) -> Result<Response, Error> {
    let arrived = arrival.map_or_else(std::time::Instant::now, |a| a.0.0);
    let text = body.directive.text.clone();
    let decision = app.core.clarify(body.into(), text.as_deref(), arrived).await?;
    crate::transport::answer(decision, move |decision| {
        decision_json(&DecisionDto::new(decision, text), decision.interpretations.len())
    })
    .await
}

/// What an answer's JSON takes, in bytes: about 300 besides its readings, and about 150 to 280
/// a reading (the paper's two take 800 in all; 99,856 readings about 20 MB).
const ANSWER_BYTES: usize = 384;
const READING_BYTES: usize = 256;

/// The answer as `Json` writes it, the same bytes, into one buffer sized for it: `Json` starts
/// from 128 bytes and grows through `BytesMut` a write at a time.
fn decision_json(answer: &DecisionDto, readings: usize) -> Response {
    let mut body = Vec::with_capacity(ANSWER_BYTES + READING_BYTES * readings);
    match serde_json::to_writer(&mut body, answer) {
        Ok(()) => (
            [(header::CONTENT_TYPE, HeaderValue::from_static("application/json"))],
            body,
        )
            .into_response(),
        Err(e) => Error::Internal(format!("writing the answer failed: {e}")).into_response(),
    }
}

#[utoipa::path(post, path = "/v1/check", tag = "clarify",
    summary = "Check the next step, or the rest of a plan, under the norms in force now",
    description = "For a robot partway through a plan: simulates the given steps in order from the current scene and says whether each is still permissible and feasible, with reasons and the norm version.",
    request_body(content = CheckBody, example = json!({"scene": {"agent": {"position": [0, 0, 0.75], "reach": 0.9}, "objects": [{"id": "object4", "type": "vase", "position": [0.6, 0.35, 0.85]}]}, "steps": ["get(object4)"]})),
    responses(
        (status = 200, description = "Each step's verdict, and whether all may be done", body = CheckDto,
         example = json!({"permitted": true, "steps": [{"step": "get(object4)", "permissible": true, "feasible": true, "reasons": [], "plan": ["get(object4)"]}], "utterance": "Okay.", "norm_version": 3})),
        (status = 422, description = "A field is wrong; `field` points at it", body = Problem, content_type = PROBLEM_JSON),
        doc::problems::FailClosed,
        doc::problems::JsonBody,
    ))]
async fn check(
    State(app): State<AppState>,
    arrival: Option<Extension<Arrival>>,
    JsonBody(body): JsonBody<CheckBody>,
) -> Result<Json<CheckDto>, Error> {
    let arrived = arrival.map_or_else(std::time::Instant::now, |a| a.0.0);
    let check = app.core.check(body.into(), arrived).await?;
    Ok(Json(CheckDto::from(&check)))
}

/// A verb name from the path.
fn verb_name(text: &str) -> Result<&str, Error> {
    if text.is_empty() || text.len() > crate::engine::action::MAX_VERB_LEN {
        return Err(Error::NotFound {
            what: format!("verb `{text}`"),
        });
    }
    Ok(text)
}

#[utoipa::path(get, path = "/v1/actions", tag = "actions",
    summary = "Every verb of the action library, by name",
    security((), ("token" = [])),
    responses(
        (status = 200, description = "The verbs", body = Vec<ActionSchema>),
        doc::problems::Store,
        doc::problems::ReadToken,
    ))]
async fn list_actions(State(app): State<AppState>, _: Reader) -> Result<Json<Vec<ActionInput>>, Error> {
    Ok(Json(app.core.list_actions().await?))
}

#[utoipa::path(get, path = "/v1/actions/{name}", tag = "actions",
    summary = "One verb",
    security((), ("token" = [])),
    params(("name" = String, Path, description = "The verb, e.g. `put`")),
    responses(
        (status = 200, description = "The verb", body = ActionSchema,
         example = json!({"name": "put", "parameters": ["X", "Y"], "joiner": "on", "methods": [{"steps": ["get(X)", "itself"], "reach": ["X", "Y"], "place": ["X", "Y"], "adds": ["on(X,Y)"], "removes": ["holding(self,X)"]}]})),
        doc::problems::NoVerb,
        doc::problems::Store,
        doc::problems::ReadToken,
    ))]
async fn get_action(
    State(app): State<AppState>,
    _: Reader,
    Path(name): Path<String>,
) -> Result<Json<ActionInput>, Error> {
    Ok(Json(app.core.get_action(verb_name(&name)?).await?))
}

#[utoipa::path(put, path = "/v1/actions/{name}", tag = "actions",
    summary = "Add or replace a verb; nothing is stored unless it is valid and its steps do not loop",
    params(("name" = String, Path, description = "The verb, e.g. `open`")),
    request_body(content = ActionSchema, example = json!({"parameters": ["X"], "methods": [{"reach": ["X"], "preconditions": ["closed(X)"], "adds": ["open(X)"], "removes": ["closed(X)"]}]})),
    security((), ("token" = [])),
    responses(
        (status = 200, description = "Replaced; the verb as stored", body = ActionSchema),
        (status = 201, description = "Added; the verb as stored", body = ActionSchema),
        (status = 422, description = "A field is wrong, or the steps would loop; `field` points at it", body = Problem, content_type = PROBLEM_JSON),
        doc::problems::Store,
        doc::problems::JsonBody,
        doc::problems::WriteToken,
    ))]
async fn put_action(
    State(app): State<AppState>,
    Writer(actor): Writer,
    Path(name): Path<String>,
    JsonBody(body): JsonBody<ActionInput>,
) -> Result<Response, Error> {
    // Not `verb_name`: a name that cannot be a verb is a 422 at `/name`, never a 404 (PUT
    // documents none).
    let (stored, created) = app.core.put_action(&name, body, &actor).await?;
    let status = if created { StatusCode::CREATED } else { StatusCode::OK };
    Ok((status, Json(stored)).into_response())
}

#[utoipa::path(delete, path = "/v1/actions/{name}", tag = "actions",
    summary = "Remove a verb; readings that use it become `unknown_action`",
    description = "A verb another verb calls in a method (`get`, which the default `put` calls) is not removed: the answer is 409 naming the verbs that call it, and nothing changes. Change or remove them first.",
    params(("name" = String, Path, description = "The verb")),
    security((), ("token" = [])),
    responses(
        (status = 204, description = "Removed"),
        doc::problems::NoVerb,
        (status = 409, description = "Other verbs call it in their methods; the detail names them", body = Problem, content_type = PROBLEM_JSON,
         example = json!({"type": "/problems/verb-in-use", "title": "Verb in use", "status": 409, "detail": "verb `get` is called by `put`: change or remove them first"})),
        doc::problems::Store,
        doc::problems::WriteToken,
    ))]
async fn delete_action(
    State(app): State<AppState>,
    Writer(actor): Writer,
    Path(name): Path<String>,
) -> Result<StatusCode, Error> {
    app.core.delete_action(verb_name(&name)?, &actor).await?;
    Ok(StatusCode::NO_CONTENT)
}

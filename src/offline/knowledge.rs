//! What offline decisions are made under: a store's norms and verbs, read as a server reads
//! them, or a norms file in their place.

use std::path::Path;
use std::sync::Arc;

use super::{Failure, Knowledge, read_input};
use crate::core::{Core, Settings, norm_to_create, validate_norm_set};
use crate::engine::Library;
use crate::engine::norms::{CompiledNorms, Norm, NormSpec};
use crate::error::Error;
use crate::storage::{self, NormStore, PostgresStore, SqliteStore};
use crate::wire::{NormBody, NormSetBody, parse_json};

/// The version a freshly migrated store gives the default library: offline answers without a
/// store then carry the `library_version` a fresh server's would.
const FRESH_LIBRARY_VERSION: i64 = 1;

/// Where the norms and the library come from: a store, if one is named, else no norms and the
/// default library; a norms file replaces the store's norms.
pub struct Sources {
    /// A core over the store, used only to read what it holds, as a server would.
    store: Option<Core>,
}

impl Sources {
    /// Opens the store at `database_url` (a SQLite file, or a PostgreSQL database as the server
    /// opens it), which must already hold a store: one created here would be empty and
    /// silently decide under no norms. Opening migrates an older store.
    pub async fn open(database_url: Option<&str>) -> Result<Sources, Failure> {
        let Some(url) = database_url else {
            return Ok(Sources { store: None });
        };
        let run = |e: crate::storage::StoreError| Failure::Run { detail: e.to_string() };
        let store: Arc<dyn NormStore> = if storage::is_postgres(url) {
            match PostgresStore::open_existing(url).await.map_err(run)? {
                Some(store) => Arc::new(store),
                // The URL may carry a password: it is not repeated.
                None => {
                    return Err(Failure::Usage {
                        detail: "no Scruple store in the PostgreSQL database of --database-url (it has no norm \
                                 set): serve it once with `scruple serve`, or name the database that holds one"
                            .to_owned(),
                    });
                }
            }
        } else {
            if let Some(path) = sqlite_file(url)
                && !path.exists()
            {
                return Err(Failure::Usage {
                    detail: format!("no database at `{}` (from --database-url {url})", path.display()),
                });
            }
            Arc::new(SqliteStore::open(url).await.map_err(run)?)
        };
        let core = Core::new(store, Arc::default(), Settings::default());
        Ok(Sources { store: Some(core) })
    }

    pub fn has_store(&self) -> bool {
        self.store.is_some()
    }

    /// The norms of `norms_file` (at most `limit` bytes) when given, else the store's, else
    /// none (version 0); with the store's library, else the default one.
    pub async fn knowledge(&self, norms_file: Option<&Path>, limit: usize) -> Result<Knowledge, Failure> {
        let stored = match &self.store {
            Some(core) => Some(core.knowledge().await.map_err(|e| Failure::Run {
                detail: e.problem().detail,
            })?),
            None => None,
        };
        let library = match &stored {
            Some(k) => k.library.clone(),
            None => {
                let mut library = Library::default_library();
                library.version = FRESH_LIBRARY_VERSION;
                Arc::new(library)
            }
        };
        let norms = match (norms_file, stored) {
            (Some(path), _) => Arc::new(norms_from_file(path, limit)?),
            (None, Some(k)) => k.norms,
            (None, None) => Arc::new(CompiledNorms::compile(0, Vec::new())),
        };
        Ok(Knowledge { norms, library })
    }
}

/// The file behind a SQLite URL, unless it names an in-memory database.
fn sqlite_file(url: &str) -> Option<&Path> {
    let rest = url.strip_prefix("sqlite://").or_else(|| url.strip_prefix("sqlite:"))?;
    let (path, query) = rest.split_once('?').unwrap_or((rest, ""));
    if path.is_empty() || path == ":memory:" || query.split('&').any(|p| p == "mode=memory") {
        return None;
    }
    Some(Path::new(path))
}

/// Reads a norms file of at most `limit` bytes: a JSON list of norms as `POST /v1/norms` takes
/// them, or a norm set as `GET /v1/norm-set` gives it. Numbered as the server would number them
/// on an empty store.
pub fn norms_from_file(path: &Path, limit: usize) -> Result<CompiledNorms, Failure> {
    let bytes = read_input(path, limit)?;
    norms_from_bytes(&bytes).map_err(|error| Failure::Input {
        file: path.display().to_string(),
        error,
    })
}

/// A list is taken as if each norm were posted in turn to an empty store: ids 1, 2, ... and the
/// version the last post leaves (the count). A norm set is taken as an import on an empty store:
/// ids given are kept, the others numbered after the largest, in file order; its `version` (an
/// export's) is kept, else 1.
pub fn norms_from_bytes(bytes: &[u8]) -> Result<CompiledNorms, Error> {
    let value: serde_json::Value = parse_json(bytes)?;
    match value {
        serde_json::Value::Array(_) => {
            let bodies: Vec<NormBody> = parse_json(bytes)?;
            let mut norms = Vec::with_capacity(bodies.len());
            for (i, body) in bodies.into_iter().enumerate() {
                let at = |e: Error| match e {
                    Error::Invalid { field, detail } => Error::invalid(format!("/{i}{field}"), detail),
                    other => other,
                };
                let spec = norm_to_create(body.id, body.into_input()).map_err(at)?;
                let id = i as i64 + 1;
                norms.push(Norm { id, revision: id, spec });
            }
            Ok(CompiledNorms::compile(norms.len() as i64, norms))
        }
        serde_json::Value::Object(_) => {
            let set: NormSetBody = parse_json(bytes)?;
            let version = set.version.unwrap_or(1);
            let inputs = set.norms.into_iter().map(|n| (n.id, n.into_input())).collect();
            let specs: Vec<(Option<i64>, NormSpec)> = validate_norm_set(inputs)?;
            let mut next = specs.iter().filter_map(|(id, _)| *id).max().unwrap_or(0);
            let norms = specs
                .into_iter()
                .map(|(id, spec)| {
                    let id = id.unwrap_or_else(|| {
                        next += 1;
                        next
                    });
                    Norm {
                        id,
                        revision: version,
                        spec,
                    }
                })
                .collect();
            Ok(CompiledNorms::compile(version, norms))
        }
        _ => Err(Error::invalid(
            "",
            "a norms file is a list of norms or a norm set {\"version\": N, \"norms\": [...]}",
        )),
    }
}

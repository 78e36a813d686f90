//! TLS on the one port (rustls, ALPN `h2` then `http/1.1`), so REST, gRPC and bearer tokens never
//! cross the network in clear where no ingress terminates TLS.
//!
//! Owns: reading the PEM files, taking up renewed ones without a restart, and handshakes, done
//! on each connection's own task (never the accept loop's) so that one slow client cannot hold
//! up the others.
//! Must not: know about HTTP; above the TLS stream everything is as in cleartext.

use std::net::SocketAddr;
use std::path::{Path, PathBuf};
use std::sync::{Arc, RwLock};
use std::time::{Duration, SystemTime};

use rustls::ServerConfig;
use rustls::crypto::CryptoProvider;
use rustls::pki_types::pem::PemObject;
use rustls::pki_types::{CertificateDer, PrivateKeyDer};
use rustls::server::{ClientHello, ResolvesServerCert};
use rustls::sign::CertifiedKey;
use tokio::net::TcpStream;
use tokio::sync::{OwnedSemaphorePermit, Semaphore};
use tokio::task::JoinHandle;
use tokio_rustls::TlsAcceptor;
use tokio_rustls::server::TlsStream;

/// How often the certificate and key files are checked for a renewal.
pub const RELOAD_INTERVAL: Duration = Duration::from_secs(5);
/// A client that has not finished its handshake by then is dropped.
const HANDSHAKE_TIMEOUT: Duration = Duration::from_secs(10);
/// Handshakes in progress at once; beyond that, new connections wait in the kernel's backlog.
/// Each holds a few tens of KiB of rustls buffers, so this bounds that memory to tens of MiB.
const MAX_HANDSHAKES: usize = 1024;

/// `--tls-cert` and `--tls-key`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct TlsFiles {
    /// PEM: the server's certificate first, then any intermediates.
    pub cert: PathBuf,
    /// PEM: the private key (PKCS#8, PKCS#1 or SEC1) of the first certificate.
    pub key: PathBuf,
}

/// When each file last changed, as far as the file system tells; a renewal changes it.
type Stamp = [Option<(SystemTime, u64)>; 2];

fn stamp(files: &TlsFiles) -> Stamp {
    let of = |path: &Path| {
        std::fs::metadata(path)
            .ok()
            .and_then(|m| Some((m.modified().ok()?, m.len())))
    };
    [of(&files.cert), of(&files.key)]
}

/// The certificate chain and key of `files`, checked to belong together. Errors name the flag
/// and the file.
fn load(files: &TlsFiles, provider: &CryptoProvider) -> Result<CertifiedKey, String> {
    let cert_path = files.cert.display();
    let key_path = files.key.display();
    let chain = CertificateDer::pem_file_iter(&files.cert)
        .map_err(|e| format!("--tls-cert {cert_path}: {e}"))?
        .collect::<Result<Vec<_>, _>>()
        .map_err(|e| format!("--tls-cert {cert_path}: {e}"))?;
    if chain.is_empty() {
        return Err(format!("--tls-cert {cert_path}: no PEM CERTIFICATE in it"));
    }
    let key = PrivateKeyDer::from_pem_file(&files.key).map_err(|e| match e {
        rustls::pki_types::pem::Error::NoItemsFound => format!("--tls-key {key_path}: no PEM private key in it"),
        e => format!("--tls-key {key_path}: {e}"),
    })?;
    CertifiedKey::from_der(chain, key, provider).map_err(|e| match e {
        rustls::Error::InconsistentKeys(_) => {
            format!("--tls-key {key_path} is not the key of the certificate in --tls-cert {cert_path}")
        }
        e => format!("--tls-key {key_path} with --tls-cert {cert_path}: {e}"),
    })
}

/// Hands every handshake the certificate in force; a watcher replaces it when the files change.
#[derive(Debug)]
struct Current {
    key: RwLock<Arc<CertifiedKey>>,
}

impl Current {
    fn get(&self) -> Arc<CertifiedKey> {
        // A poisoned lock still holds a whole certificate: swaps are single assignments.
        self.key.read().unwrap_or_else(|e| e.into_inner()).clone()
    }

    fn set(&self, key: CertifiedKey) {
        *self.key.write().unwrap_or_else(|e| e.into_inner()) = Arc::new(key);
    }
}

impl ResolvesServerCert for Current {
    fn resolve(&self, _hello: ClientHello<'_>) -> Option<Arc<CertifiedKey>> {
        Some(self.get())
    }
}

/// TLS, loaded and checked; `listen` puts it in front of a TCP listener.
pub struct Tls {
    files: TlsFiles,
    provider: Arc<CryptoProvider>,
    current: Arc<Current>,
    config: Arc<ServerConfig>,
}

impl Tls {
    /// Reads and checks the files; an error names the flag, the file and what is wrong.
    pub fn load(files: TlsFiles) -> Result<Tls, String> {
        let provider = Arc::new(rustls::crypto::ring::default_provider());
        let current = Arc::new(Current {
            key: RwLock::new(Arc::new(load(&files, &provider)?)),
        });
        let mut config = ServerConfig::builder_with_provider(provider.clone())
            .with_safe_default_protocol_versions()
            .map_err(|e| format!("TLS: {e}"))?
            .with_no_client_auth()
            .with_cert_resolver(current.clone());
        // gRPC clients require h2; browsers and curl take whichever they prefer.
        config.alpn_protocols = vec![b"h2".to_vec(), b"http/1.1".to_vec()];
        Ok(Tls {
            files,
            provider,
            current,
            config: Arc::new(config),
        })
    }

    /// Starts taking up renewed files; the handshakes are `Handshakes::handshake`. Needs a Tokio
    /// runtime.
    pub fn start(self) -> Handshakes {
        tracing::info!(cert = %self.files.cert.display(), "serving REST and gRPC over TLS");
        let acceptor = TlsAcceptor::from(self.config.clone());
        let watching = tokio::spawn(watch(self.files, self.provider, self.current));
        Handshakes {
            acceptor,
            turns: Arc::new(Semaphore::new(MAX_HANDSHAKES)),
            watching,
        }
    }
}

/// TLS in front of the accept loop: a turn to handshake before each accept, the handshake on the
/// connection's task. Dropping it stops watching the files.
pub struct Handshakes {
    acceptor: TlsAcceptor,
    turns: Arc<Semaphore>,
    watching: JoinHandle<()>,
}

impl Drop for Handshakes {
    fn drop(&mut self) {
        self.watching.abort();
    }
}

impl Handshakes {
    /// Waits for one of the `MAX_HANDSHAKES` turns: the accept loop takes one before accepting,
    /// so that beyond them new connections wait in the kernel's backlog.
    pub async fn turn(&self) -> OwnedSemaphorePermit {
        // The semaphore is never closed.
        self.turns
            .clone()
            .acquire_owned()
            .await
            .unwrap_or_else(|_| unreachable!("the handshake semaphore is never closed"))
    }

    /// The handshake on `stream`, within `HANDSHAKE_TIMEOUT`; `None` when it fails (scanners and
    /// cleartext clients land there: logged at debug). The turn ends with the handshake.
    pub async fn handshake(
        &self,
        stream: TcpStream,
        peer: SocketAddr,
        turn: OwnedSemaphorePermit,
    ) -> Option<TlsStream<TcpStream>> {
        let outcome = tokio::time::timeout(HANDSHAKE_TIMEOUT, self.acceptor.accept(stream)).await;
        drop(turn);
        match outcome {
            Ok(Ok(tls)) => Some(tls),
            Ok(Err(error)) => {
                tracing::debug!(%peer, %error, "TLS handshake failed");
                None
            }
            Err(_) => {
                tracing::debug!(%peer, "TLS handshake timed out");
                None
            }
        }
    }
}

/// Takes up a renewed certificate: when either file changes, both are read again and, if they
/// load and belong together, used for the next handshake. Until then the old pair stays.
async fn watch(files: TlsFiles, provider: Arc<CryptoProvider>, current: Arc<Current>) {
    let mut seen = stamp(&files);
    let mut ticks = tokio::time::interval(RELOAD_INTERVAL);
    ticks.set_missed_tick_behavior(tokio::time::MissedTickBehavior::Delay);
    loop {
        ticks.tick().await;
        let now = stamp(&files);
        if now == seen {
            continue;
        }
        seen = now;
        match load(&files, &provider) {
            Ok(key) => {
                current.set(key);
                tracing::info!(cert = %files.cert.display(), "TLS certificate reloaded");
            }
            // A renewal may write the two files one after the other; the second write retries.
            Err(error) => tracing::warn!(%error, "TLS certificate not reloaded; the previous one stays in use"),
        }
    }
}

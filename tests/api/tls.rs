//! TLS: REST and gRPC on the one port over rustls, with certificates the tests make (rcgen).
//! Clients trust only the test's certificate, so a passing request proves the server presented it.

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::{Duration, Instant};

use reqwest::{Client, StatusCode, Version};
use rustls::pki_types::CertificateDer;
use rustls::pki_types::pem::PemObject;
use scruple::transport::grpc::pb::clarifier_client::ClarifierClient;
use scruple::transport::tls::{RELOAD_INTERVAL, TlsFiles};
use serde_json::{Value, json};
use tonic::transport::{Certificate, Channel, ClientTlsConfig};

use crate::grpc::clarify_request;
use crate::helpers::{Options, TestApp, get_vase, serve_binary, spawn_with};

/// A self-signed certificate for `localhost` and 127.0.0.1, as PEM: (certificate, key).
fn self_signed() -> (String, String) {
    let made = rcgen::generate_simple_self_signed(vec!["localhost".to_owned(), "127.0.0.1".to_owned()])
        .expect("rcgen makes a certificate");
    (made.cert.pem(), made.signing_key.serialize_pem())
}

/// Writes the pair as `server.crt` / `server.key` in `dir`.
fn write_pair(dir: &Path, (cert, key): &(String, String)) -> TlsFiles {
    let files = TlsFiles {
        cert: dir.join("server.crt"),
        key: dir.join("server.key"),
    };
    std::fs::write(&files.cert, cert).unwrap();
    std::fs::write(&files.key, key).unwrap();
    files
}

/// A client that trusts `ca_pem` alone and offers `alpn` (e.g. `h2`, `http/1.1`).
fn https_client(ca_pem: &str, alpn: &[&[u8]]) -> Client {
    crate::support::install_ring();
    let mut roots = rustls::RootCertStore::empty();
    roots
        .add(CertificateDer::from_pem_slice(ca_pem.as_bytes()).unwrap())
        .unwrap();
    let mut config = rustls::ClientConfig::builder_with_provider(Arc::new(rustls::crypto::ring::default_provider()))
        .with_safe_default_protocol_versions()
        .unwrap()
        .with_root_certificates(roots)
        .with_no_client_auth();
    config.alpn_protocols = alpn.iter().map(|p| p.to_vec()).collect();
    Client::builder()
        .tls_backend_preconfigured(config)
        .timeout(Duration::from_secs(10))
        .build()
        .unwrap()
}

fn both() -> Vec<&'static [u8]> {
    vec![b"h2", b"http/1.1"]
}

/// A test server with TLS on, its certificate pair in the server's own temp dir.
async fn spawn_tls(pair: &(String, String), admin_token: Option<&str>) -> (TestApp, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let files = write_pair(dir.path(), pair);
    let app = spawn_with(Options {
        admin_token: admin_token.map(str::to_owned),
        tweak: Some(Box::new(move |config| config.tls = Some(files))),
        ..Options::default()
    })
    .await;
    // The pair lives as long as the test: keep the dir.
    let path = dir.keep();
    (app, path)
}

fn https(app: &TestApp, path: &str) -> String {
    format!("{}{path}", app.base.replace("http://", "https://"))
}

#[tokio::test]
async fn rest_and_grpc_share_the_tls_port() {
    let pair = self_signed();
    let (app, _dir) = spawn_tls(&pair, Some("tls-admin-token-0123")).await;

    // ALPN picks HTTP/2 when the client offers it, HTTP/1.1 when that is all it speaks.
    let h2 = https_client(&pair.0, &both());
    let health = h2.get(https(&app, "/healthz")).send().await.unwrap();
    assert_eq!(health.status(), StatusCode::OK);
    assert_eq!(health.version(), Version::HTTP_2);
    let h1 = https_client(&pair.0, &[b"http/1.1"]);
    let health = h1.get(https(&app, "/healthz")).send().await.unwrap();
    assert_eq!(health.status(), StatusCode::OK);
    assert_eq!(health.version(), Version::HTTP_11);

    // Two vases and no norms: ask.
    let asked: Value = h1
        .post(https(&app, "/v1/clarify"))
        .json(&get_vase())
        .send()
        .await
        .unwrap()
        .json()
        .await
        .unwrap();
    assert_eq!(asked["decision"], "ask", "{asked}");

    // The bearer token travels inside TLS; without it the write is still refused.
    let norm = json!({"kind": "forbidden_state", "state": "did(self,get(object3))"});
    let refused = h2.post(https(&app, "/v1/norms")).json(&norm).send().await.unwrap();
    assert_eq!(refused.status(), StatusCode::UNAUTHORIZED);
    let created = h2
        .post(https(&app, "/v1/norms"))
        .bearer_auth("tls-admin-token-0123")
        .json(&norm)
        .send()
        .await
        .unwrap();
    assert_eq!(created.status(), StatusCode::CREATED);

    // gRPC on the same port, same certificate, sees the new norm: the paper's assume.
    let channel = Channel::from_shared(https(&app, ""))
        .unwrap()
        .tls_config(
            ClientTlsConfig::new()
                .ca_certificate(Certificate::from_pem(&pair.0))
                .domain_name("localhost"),
        )
        .unwrap()
        .connect()
        .await
        .expect("gRPC connects over TLS");
    let answer = ClarifierClient::new(channel)
        .clarify(clarify_request(&get_vase()))
        .await
        .expect("Clarify over TLS")
        .into_inner();
    assert_eq!(answer.decision, "assume");
    assert_eq!(
        answer.utterance,
        "I am assuming you want me to get the plastic vase. I cannot get the fragile vase because it requires a forbidden state."
    );
    app.stop().await;
}

#[tokio::test]
async fn cleartext_and_untrusting_clients_get_nothing() {
    let pair = self_signed();
    let (app, _dir) = spawn_tls(&pair, None).await;

    // A cleartext request never reaches a handler: the server wants a handshake first.
    let clear = crate::helpers::http_client();
    let error = clear.get(app.url("/healthz")).send().await.unwrap_err();
    assert!(
        !error.is_timeout(),
        "a cleartext client is turned away at once: {error:?}"
    );

    // A client that trusts another certificate refuses this server.
    let other = self_signed();
    let error = https_client(&other.0, &both())
        .get(https(&app, "/healthz"))
        .send()
        .await
        .unwrap_err();
    assert!(format!("{error:?}").contains("InvalidCertificate"), "{error:?}");

    // Neither hurt the server.
    let ok = https_client(&pair.0, &both())
        .get(https(&app, "/healthz"))
        .send()
        .await
        .unwrap();
    assert_eq!(ok.status(), StatusCode::OK);
    app.stop().await;
}

/// Polls until `client` gets a 200 from `/healthz` on a new connection, or `limit` passes.
async fn served_to(make: impl Fn() -> Client, url: &str, limit: Duration) -> bool {
    let start = Instant::now();
    while start.elapsed() < limit {
        // A new client per try: a kept-alive connection would still hold the old session.
        if let Ok(response) = make().get(url).send().await {
            return response.status() == StatusCode::OK;
        }
        tokio::time::sleep(Duration::from_millis(250)).await;
    }
    false
}

#[tokio::test]
async fn a_renewed_certificate_is_taken_up_without_a_restart() {
    let first = self_signed();
    let (app, dir) = spawn_tls(&first, None).await;
    let url = https(&app, "/healthz");
    let wait = RELOAD_INTERVAL * 3 + Duration::from_secs(2);

    // A half-written renewal (garbage in the certificate file) keeps the old pair in use.
    std::fs::write(dir.join("server.crt"), "not a certificate").unwrap();
    tokio::time::sleep(RELOAD_INTERVAL * 2 + Duration::from_millis(500)).await;
    assert!(served_to(|| https_client(&first.0, &both()), &url, Duration::from_secs(5)).await);

    // The renewed pair is served on the next connections; the old certificate no longer is.
    let second = self_signed();
    write_pair(&dir, &second);
    assert!(
        served_to(|| https_client(&second.0, &both()), &url, wait).await,
        "the renewed certificate was not served within {wait:?}"
    );
    assert!(
        https_client(&first.0, &both()).get(&url).send().await.is_err(),
        "the old certificate is still served"
    );
    app.stop().await;
}

#[test]
fn the_binary_serves_tls_from_its_flags_and_refuses_bad_files() {
    let pair = self_signed();
    let dir = tempfile::tempdir().unwrap();
    let files = write_pair(dir.path(), &pair);
    let db = format!("sqlite://{}", dir.path().join("scruple.db").display());
    let (cert, key) = (files.cert.to_str().unwrap(), files.key.to_str().unwrap());

    // From the environment, as the deploy manifests set it.
    let served = serve_binary(
        &db,
        &[],
        &[("SCRUPLE_TLS_CERT", cert), ("SCRUPLE_TLS_KEY", key)],
        std::process::Stdio::null(),
    );
    let runtime = tokio::runtime::Runtime::new().unwrap();
    let status = runtime.block_on(async {
        https_client(&pair.0, &both())
            .get(format!("https://{}/healthz", served.addr))
            .send()
            .await
            .map(|r| r.status())
    });
    assert_eq!(status.unwrap(), StatusCode::OK);
    assert!(served.terminate().success());

    let start = |args: &[&str]| {
        crate::support::scruple()
            .args(["serve", "--listen", "127.0.0.1:0", "--database-url", &db])
            .args(args)
            .env("RUST_LOG", "off")
            .output()
            .unwrap()
    };
    // One without the other is a usage error.
    let alone = start(&["--tls-cert", cert]);
    assert_eq!(alone.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&alone.stderr).contains("--tls-key"));

    let missing = dir.path().join("missing.crt");
    let garbage = dir.path().join("garbage.pem");
    std::fs::write(&garbage, "-----BEGIN NOTHING-----\n").unwrap();
    let stranger = dir.path().join("stranger.key");
    std::fs::write(&stranger, self_signed().1).unwrap();
    let cases: [(&[&str], &str); 4] = [
        (
            &["--tls-cert", missing.to_str().unwrap(), "--tls-key", key],
            "--tls-cert",
        ),
        (&["--tls-cert", key, "--tls-key", key], "no PEM CERTIFICATE"),
        (
            &["--tls-cert", cert, "--tls-key", garbage.to_str().unwrap()],
            "--tls-key",
        ),
        (
            &["--tls-cert", cert, "--tls-key", stranger.to_str().unwrap()],
            "is not the key of the certificate",
        ),
    ];
    for (args, says) in cases {
        let out = start(args);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{args:?}: {stderr}");
        assert!(stderr.contains(says), "{args:?} should say {says:?}: {stderr}");
        assert!(
            out.stdout.is_empty(),
            "{args:?} must not listen: {}",
            String::from_utf8_lossy(&out.stdout)
        );
    }
}

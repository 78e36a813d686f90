//! The `scruple` binary: flags and environment, telemetry, startup, graceful shutdown.

use std::io::Write;
use std::process::ExitCode;

use clap::{Parser, Subcommand};
use scruple::app::{Application, Config, DEFAULT_MAX_BODY_BYTES};
use tracing_subscriber::EnvFilter;

#[derive(Parser)]
#[command(
    name = "scruple",
    version,
    about = "Morally sensitive clarification of ambiguous robot directives"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Serve REST on one port until SIGTERM or Ctrl-C.
    Serve {
        /// Address to listen on; port 0 picks a free port (printed as `listening on ADDR`).
        #[arg(long, env = "SCRUPLE_LISTEN", default_value = "127.0.0.1:8080")]
        listen: String,
        /// Norm store; a SQLite file is created if missing and migrated at start.
        #[arg(long, env = "SCRUPLE_DATABASE_URL", default_value = "sqlite://scruple.db")]
        database_url: String,
        /// When set, requests that change norms need `Authorization: Bearer TOKEN`.
        #[arg(long, env = "SCRUPLE_ADMIN_TOKEN", hide_env_values = true)]
        admin_token: Option<String>,
        /// Largest request body accepted, in bytes; larger ones get 413.
        #[arg(long, env = "SCRUPLE_MAX_BODY_BYTES", default_value_t = DEFAULT_MAX_BODY_BYTES)]
        max_body_bytes: usize,
    },
    /// Print the REST API's OpenAPI 3.1 document (as `openapi/openapi.json` holds it).
    Openapi,
}

async fn shutdown_signal() {
    let ctrl_c = async {
        if tokio::signal::ctrl_c().await.is_err() {
            std::future::pending::<()>().await;
        }
    };
    #[cfg(unix)]
    let terminate = async {
        match tokio::signal::unix::signal(tokio::signal::unix::SignalKind::terminate()) {
            Ok(mut signal) => {
                signal.recv().await;
            }
            Err(_) => std::future::pending::<()>().await,
        }
    };
    #[cfg(not(unix))]
    let terminate = std::future::pending::<()>();
    tokio::select! {
        () = ctrl_c => {},
        () = terminate => {},
    }
    tracing::info!("shutting down: draining in-flight requests");
}

#[tokio::main]
async fn main() -> ExitCode {
    tracing_subscriber::fmt()
        .with_env_filter(EnvFilter::try_from_default_env().unwrap_or_else(|_| EnvFilter::new("info")))
        .with_writer(std::io::stderr)
        .init();
    let Cli { command } = Cli::parse();
    match command {
        Command::Openapi => match scruple::transport::rest::openapi().to_pretty_json() {
            Ok(text) => {
                println!("{text}");
                ExitCode::SUCCESS
            }
            Err(e) => {
                eprintln!("scruple: {e}");
                ExitCode::FAILURE
            }
        },
        Command::Serve {
            listen,
            database_url,
            admin_token,
            max_body_bytes,
        } => {
            let config = Config {
                listen,
                database_url,
                admin_token,
                max_body_bytes,
            };
            let app = match Application::build(config).await {
                Ok(app) => app,
                Err(e) => {
                    tracing::error!(error = %e, "cannot start");
                    eprintln!("scruple: {e}");
                    return ExitCode::FAILURE;
                }
            };
            match app.local_addr() {
                Ok(addr) => {
                    let mut stdout = std::io::stdout().lock();
                    let _ = writeln!(stdout, "listening on {addr}");
                    let _ = stdout.flush();
                }
                Err(e) => {
                    eprintln!("scruple: {e}");
                    return ExitCode::FAILURE;
                }
            }
            if let Err(e) = app.run_until(shutdown_signal()).await {
                eprintln!("scruple: {e}");
                return ExitCode::FAILURE;
            }
            ExitCode::SUCCESS
        }
    }
}

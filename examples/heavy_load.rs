//! A bounded heavy load against a running Scruple: CLIENTS clients, each sending "Put the cup on
//! the plate." over SIZE cups × SIZE plates (SIZE² readings) again and again for SECONDS, while
//! a prober asks `/healthz` every 100 ms and a light client asks the paper's "Get the vase." every
//! 20 ms. Prints what a robot fleet would see: how late each answer came against its deadline,
//! the statuses (and problem types of the 503s), health's latency and the light requests'. A client told to retry later (503 with Retry-After) waits that long, as a robot
//! should. Traffic goes only to the address given (loopback in scripts/heavy-load.sh).
//!
//! Usage: `cargo run --release --example heavy_load -- ADDR [CLIENTS] [SECONDS] [SIZE] [DEADLINE_MS]`
//! (defaults 64, 30, 316, 2000). Exits nonzero unless every answer came within its deadline +
//! 250 ms (or was a 503 `overloaded`), no answer was `norms-unavailable`, health's p99 was
//! within 50 ms, and every light request was answered 200 with a p99 within 250 ms.

use std::collections::BTreeMap;
use std::process::ExitCode;
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use serde_json::{Value, json};

/// Slack over the deadline an answer may take: the response's encoding and the loopback trip.
const SLACK: Duration = Duration::from_millis(250);

fn scene(size: usize) -> Value {
    // Cups and plates on a table in front of the arm, metres, world frame: all within reach.
    let mut objects = Vec::with_capacity(2 * size);
    for i in 0..size {
        let y = -0.3 + 0.6 * i as f64 / size as f64;
        objects.push(json!({"id": format!("cup{i}"), "type": "cup", "position": [0.4, y, 0.8]}));
        objects.push(json!({"id": format!("plate{i}"), "type": "plate", "position": [0.5, y, 0.76]}));
    }
    json!({"agent": {"position": [0, 0, 0.75], "reach": 0.9}, "objects": objects})
}

#[derive(Default)]
struct Tally {
    /// By status, and for a 503 its problem type.
    outcomes: BTreeMap<String, u64>,
    /// Answer latencies (send to response head), for 200s.
    answered: Vec<Duration>,
    /// Answers that came later than deadline + SLACK.
    late: u64,
    latest: Duration,
    health: Probe,
    /// The paper's "Get the vase.", asked beside the heavy requests.
    light: Probe,
}

/// A request sent at a steady pace: each one's latency, and how many were not answered 2xx.
#[derive(Default)]
struct Probe {
    times: Vec<Duration>,
    failures: u64,
}

impl Probe {
    /// Prints one line of the probe's latencies (sorted first); returns its p99.
    fn report(&mut self, name: &str, sent: &str, failed: &str) -> Duration {
        self.times.sort();
        let p99 = quantile(&self.times, 0.99);
        println!(
            "  {name}: {} {sent}, p50 {}, p99 {}, max {}, {failed}: {}",
            self.times.len(),
            ms(quantile(&self.times, 0.5)),
            ms(p99),
            ms(self.times.last().copied().unwrap_or_default()),
            self.failures
        );
        p99
    }
}

/// Sends `request` every `every` until `until`, recording each outcome in the probe `of` picks.
fn probe(
    request: reqwest::RequestBuilder,
    every: Duration,
    until: Instant,
    tally: Arc<Mutex<Tally>>,
    of: fn(&mut Tally) -> &mut Probe,
) -> tokio::task::JoinHandle<()> {
    let request = request.timeout(Duration::from_secs(10));
    tokio::spawn(async move {
        while Instant::now() < until {
            let sent = Instant::now();
            let ok =
                (request.try_clone().expect("a body in memory").send().await).is_ok_and(|r| r.status().is_success());
            {
                let mut t = tally.lock().unwrap();
                let probe = of(&mut t);
                probe.times.push(sent.elapsed());
                probe.failures += u64::from(!ok);
            }
            tokio::time::sleep(every).await;
        }
    })
}

/// The paper's "Get the vase." in its lab scene: a request a robot sends while others are heavy.
fn light_body() -> Vec<u8> {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../shared/scenarios/paper-demo.json");
    let demo: Value = serde_json::from_str(&std::fs::read_to_string(path).expect("paper-demo.json")).expect("JSON");
    serde_json::to_vec(&json!({
        "directive": {"action": "get", "arguments": [{"type": "vase"}], "text": "Get the vase."},
        "scene": demo["scenes"]["lab"],
    }))
    .expect("the body is JSON")
}

fn quantile(sorted: &[Duration], q: f64) -> Duration {
    if sorted.is_empty() {
        return Duration::ZERO;
    }
    sorted[((sorted.len() - 1) as f64 * q).round() as usize]
}

fn ms(d: Duration) -> String {
    format!("{:.1} ms", d.as_secs_f64() * 1000.0)
}

#[tokio::main]
async fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let Some(addr) = args.first() else {
        eprintln!("usage: heavy_load ADDR [CLIENTS] [SECONDS] [SIZE] [DEADLINE_MS]");
        return ExitCode::from(2);
    };
    let number = |i: usize, default: u64| args.get(i).and_then(|a| a.parse().ok()).unwrap_or(default);
    let (clients, seconds, size, deadline_ms) = (number(1, 64), number(2, 30), number(3, 316), number(4, 2000));
    let deadline = Duration::from_millis(deadline_ms);
    let body = Arc::new(
        serde_json::to_vec(&json!({
            "directive": {"action": "put", "arguments": [{"type": "cup"}, {"type": "plate"}]},
            "scene": scene(size as usize),
            "options": {"deadline_ms": deadline_ms, "max_readings": 100_000},
        }))
        .expect("the body is JSON"),
    );
    // reqwest's rustls has no provider of its own here (cleartext, but it is built in).
    let _ = rustls::crypto::ring::default_provider().install_default();
    let client = reqwest::Client::builder()
        .pool_max_idle_per_host(clients as usize)
        .build()
        .expect("a client");
    let tally = Arc::new(Mutex::new(Tally::default()));
    let until = Instant::now() + Duration::from_secs(seconds);

    let mut tasks = Vec::new();
    for _ in 0..clients {
        let (client, body, tally) = (client.clone(), body.clone(), tally.clone());
        let url = format!("http://{addr}/v1/clarify");
        tasks.push(tokio::spawn(async move {
            while Instant::now() < until {
                let sent = Instant::now();
                let response = client
                    .post(&url)
                    .header("content-type", "application/json")
                    .body(body.as_ref().clone())
                    .timeout(Duration::from_secs(120))
                    .send()
                    .await;
                let took = sent.elapsed();
                let outcome = match response {
                    Err(e) => format!("error: {}", if e.is_timeout() { "timeout" } else { "connection" }),
                    Ok(r) => {
                        let status = r.status().as_u16();
                        // A well-behaved client waits as long as a 503 asks before trying again.
                        let retry_after = (r.headers().get("retry-after"))
                            .and_then(|v| v.to_str().ok()?.parse::<u64>().ok())
                            .map(Duration::from_secs);
                        let text = r.bytes().await.unwrap_or_default();
                        if let Some(wait) = retry_after {
                            tokio::time::sleep(wait.min(until.saturating_duration_since(Instant::now()))).await;
                        }
                        if status == 200 {
                            let mut t = tally.lock().unwrap();
                            t.answered.push(took);
                            if took > deadline + SLACK {
                                t.late += 1;
                            }
                            t.latest = t.latest.max(took);
                            "200".to_owned()
                        } else {
                            let problem: Value = serde_json::from_slice(&text).unwrap_or(Value::Null);
                            format!("{status} {}", problem["type"].as_str().unwrap_or("?"))
                        }
                    }
                };
                *tally.lock().unwrap().outcomes.entry(outcome).or_default() += 1;
            }
        }));
    }
    let health = probe(
        client.get(format!("http://{addr}/healthz")),
        Duration::from_millis(100),
        until,
        tally.clone(),
        |t| &mut t.health,
    );
    let light = probe(
        (client.post(format!("http://{addr}/v1/clarify")))
            .header("content-type", "application/json")
            .body(light_body()),
        Duration::from_millis(20),
        until,
        tally.clone(),
        |t| &mut t.light,
    );
    for task in tasks {
        let _ = task.await;
    }
    let _ = health.await;
    let _ = light.await;

    let mut t = tally.lock().unwrap();
    t.answered.sort();
    println!(
        "clients {clients}, {seconds} s, {size} cups x {size} plates ({} readings), deadline {deadline_ms} ms",
        size * size
    );
    for (outcome, n) in &t.outcomes {
        println!("  {outcome}: {n}");
    }
    println!(
        "  answers: p50 {}, p99 {}, latest {}; later than deadline + {}: {}",
        ms(quantile(&t.answered, 0.5)),
        ms(quantile(&t.answered, 0.99)),
        ms(t.latest),
        ms(SLACK),
        t.late
    );
    let health_p99 = t.health.report("/healthz", "probes", "failed");
    let light_p99 = t.light.report("light \"Get the vase.\"", "asked", "not 200");
    let unavailable: u64 = t
        .outcomes
        .iter()
        .filter(|(k, _)| !(k.as_str() == "200" || k.as_str() == "503 /problems/overloaded"))
        .map(|(_, n)| n)
        .sum();
    let ok = t.late == 0
        && unavailable == 0
        && health_p99 <= Duration::from_millis(50)
        && t.health.failures == 0
        && light_p99 <= SLACK
        && t.light.failures == 0;
    println!("  verdict: {}", if ok { "PASS" } else { "FAIL" });
    if ok { ExitCode::SUCCESS } else { ExitCode::FAILURE }
}

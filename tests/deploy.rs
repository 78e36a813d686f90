//! Keeps `deploy/` honest: the Dockerfile and the Kubernetes manifests must agree with the binary
//! they ship and with each other.
//!
//! Pins: every `SCRUPLE_*` variable named anywhere under `deploy/` is one `scruple serve --help`
//! lists (three flags still being added are allowed while absent); one port from `SCRUPLE_LISTEN`
//! through `EXPOSE`, the container port, the Service and the probes; the readiness path and the gRPC
//! health check really answer on the real binary started with the ConfigMap's and Secret's values;
//! a non-root numeric user in both the image and the pod; every ConfigMap/Secret reference resolves
//! and every key is read; Secrets hold only placeholders; the kustomization lists every manifest but
//! the PostgreSQL example; the image builds the locked binary, profile-guided, with a new enough
//! toolchain, from a context that holds what the training reads. And CI (`.ci/run`) tests with
//! the command the README opens with.
//!
//! Nothing here builds an image or talks to a cluster: it reads the files and runs the binary.

mod support;

use std::collections::{BTreeMap, BTreeSet};
use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Child, Stdio};

use serde::Deserialize;
use serde_yaml_ng::Value;

/// The manifest that is an example to apply by hand, not part of the kustomization.
const POSTGRES_EXAMPLE: &str = "postgres-example.yaml";

fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn read(path: &Path) -> String {
    std::fs::read_to_string(path).unwrap_or_else(|e| panic!("reading {}: {e}", path.display()))
}

/// Every file under `dir`, recursively, sorted.
fn files_under(dir: &Path) -> Vec<PathBuf> {
    let mut files = Vec::new();
    let mut pending = vec![dir.to_owned()];
    while let Some(dir) = pending.pop() {
        for entry in std::fs::read_dir(&dir).unwrap_or_else(|e| panic!("listing {}: {e}", dir.display())) {
            let path = entry.unwrap().path();
            if path.is_dir() {
                pending.push(path);
            } else {
                files.push(path);
            }
        }
    }
    files.sort();
    files
}

fn relative(path: &Path) -> String {
    path.strip_prefix(repo()).unwrap_or(path).display().to_string()
}

// ---------------------------------------------------------------------------------------------
// The manifests

/// One YAML document of `deploy/k8s`, with the file it came from.
struct Manifest {
    file: String,
    doc: Value,
}

impl Manifest {
    fn kind(&self) -> &str {
        self.doc["kind"].as_str().unwrap_or("")
    }

    fn name(&self) -> &str {
        self.doc["metadata"]["name"].as_str().unwrap_or("")
    }

    fn what(&self) -> String {
        format!("{} {}/{}", self.file, self.kind(), self.name())
    }
}

fn k8s_dir() -> PathBuf {
    repo().join("deploy/k8s")
}

fn yaml_files() -> Vec<PathBuf> {
    files_under(&k8s_dir())
        .into_iter()
        .filter(|p| matches!(p.extension().and_then(|e| e.to_str()), Some("yaml" | "yml")))
        .collect()
}

/// Every document of every YAML file under `deploy/k8s` (a file may hold several, split by `---`).
fn all_documents() -> Vec<Manifest> {
    let mut manifests = Vec::new();
    for path in yaml_files() {
        let text = read(&path);
        let file = relative(&path);
        for (i, document) in serde_yaml_ng::Deserializer::from_str(&text).enumerate() {
            let doc = Value::deserialize(document).unwrap_or_else(|e| panic!("{file}: document {i} is not YAML: {e}"));
            if doc.is_null() {
                continue;
            }
            assert!(
                doc["apiVersion"].is_string() && doc["kind"].is_string(),
                "{file}: document {i} has no apiVersion or kind"
            );
            manifests.push(Manifest {
                file: file.clone(),
                doc,
            });
        }
    }
    manifests
}

/// The Kubernetes objects, without the kustomization itself.
fn objects() -> Vec<Manifest> {
    all_documents()
        .into_iter()
        .filter(|m| m.kind() != "Kustomization")
        .collect()
}

/// The objects `kubectl apply -k deploy/k8s` creates (everything but the PostgreSQL example).
fn kustomized() -> Vec<Manifest> {
    objects()
        .into_iter()
        .filter(|m| !m.file.ends_with(POSTGRES_EXAMPLE))
        .collect()
}

fn the<'a>(manifests: &'a [Manifest], kind: &str) -> &'a Manifest {
    let found: Vec<&Manifest> = manifests.iter().filter(|m| m.kind() == kind).collect();
    assert_eq!(
        found.len(),
        1,
        "expected exactly one {kind} in the kustomization, found {:?}",
        found.iter().map(|m| m.what()).collect::<Vec<_>>()
    );
    found[0]
}

/// The Deployment's first (only) container.
fn container(deployment: &Manifest) -> &Value {
    let containers = deployment.doc["spec"]["template"]["spec"]["containers"]
        .as_sequence()
        .unwrap_or_else(|| panic!("{} has no containers", deployment.what()));
    assert_eq!(containers.len(), 1, "{} should run one container", deployment.what());
    &containers[0]
}

/// A ConfigMap's `data` or a Secret's `stringData`/`data`, as key → value.
fn entries(manifest: &Manifest) -> BTreeMap<String, String> {
    let mut entries = BTreeMap::new();
    for field in ["data", "stringData"] {
        if let Some(map) = manifest.doc[field].as_mapping() {
            for (key, value) in map {
                let key = key
                    .as_str()
                    .unwrap_or_else(|| panic!("{}: a non-string key", manifest.what()));
                let value = match value {
                    Value::String(s) => s.clone(),
                    other => panic!(
                        "{}: {key} is {other:?}; ConfigMap and Secret values must be quoted strings",
                        manifest.what()
                    ),
                };
                entries.insert(key.to_owned(), value);
            }
        }
    }
    entries
}

fn port_of_listen(listen: &str, whence: &str) -> u16 {
    listen
        .rsplit_once(':')
        .and_then(|(_, port)| port.parse().ok())
        .unwrap_or_else(|| panic!("{whence}: SCRUPLE_LISTEN {listen:?} has no port"))
}

fn as_u64(value: &Value, whence: &str) -> u64 {
    value
        .as_u64()
        .unwrap_or_else(|| panic!("{whence} is {value:?}, not a number"))
}

// ---------------------------------------------------------------------------------------------
// The Dockerfile, read line by line

struct Instruction {
    /// 0 for the first `FROM`'s stage, counting up.
    stage: usize,
    keyword: String,
    args: String,
    line: usize,
}

fn dockerfile_path() -> PathBuf {
    repo().join("deploy/Dockerfile")
}

/// The instructions, with `\` continuations joined and comments dropped.
fn dockerfile() -> Vec<Instruction> {
    let text = read(&dockerfile_path());
    let mut instructions = Vec::new();
    let mut stage = None::<usize>;
    let mut current = String::new();
    let mut first_line = 0;
    for (i, raw) in text.lines().enumerate() {
        let line = raw.trim();
        if current.is_empty() && (line.is_empty() || line.starts_with('#')) {
            continue;
        }
        if current.is_empty() {
            first_line = i + 1;
        } else if line.starts_with('#') {
            continue;
        }
        if let Some(head) = line.strip_suffix('\\') {
            current.push_str(head);
            current.push(' ');
            continue;
        }
        current.push_str(line);
        let (keyword, args) = current.split_once(char::is_whitespace).unwrap_or((&current, ""));
        let keyword = keyword.to_ascii_uppercase();
        if keyword == "FROM" {
            stage = Some(stage.map_or(0, |s| s + 1));
        }
        instructions.push(Instruction {
            stage: stage.unwrap_or_else(|| panic!("deploy/Dockerfile:{first_line}: {keyword} before any FROM")),
            keyword,
            args: args.trim().to_owned(),
            line: first_line,
        });
        current.clear();
    }
    instructions
}

/// What a `COPY` takes from the context: its arguments but the flags and the destination.
fn copy_sources(copy: &Instruction) -> Vec<&str> {
    let mut words: Vec<&str> = copy.args.split_whitespace().filter(|w| !w.starts_with("--")).collect();
    words.pop();
    words
}

/// Whether `path` is `dir` or lies under it (paths relative to the repository, `dir` with or
/// without its trailing `/`).
fn within(path: &str, dir: &str) -> bool {
    let dir = dir.trim_end_matches('/');
    path == dir || path.strip_prefix(dir).is_some_and(|rest| rest.starts_with('/'))
}

fn final_stage(instructions: &[Instruction]) -> Vec<&Instruction> {
    let last = instructions
        .iter()
        .map(|i| i.stage)
        .max()
        .expect("deploy/Dockerfile has a FROM");
    instructions.iter().filter(|i| i.stage == last).collect()
}

/// `ENV A=1 B=2` (or the old `ENV A 1`) of the given stage's instructions, as name → value.
fn env_of(stage: &[&Instruction]) -> BTreeMap<String, String> {
    let mut env = BTreeMap::new();
    for instruction in stage.iter().filter(|i| i.keyword == "ENV") {
        let args = instruction.args.as_str();
        let first = args.split_whitespace().next().unwrap_or("");
        if first.contains('=') {
            for pair in args.split_whitespace() {
                let (name, value) = pair
                    .split_once('=')
                    .unwrap_or_else(|| panic!("deploy/Dockerfile:{}: ENV {pair:?}", instruction.line));
                env.insert(name.to_owned(), value.trim_matches('"').to_owned());
            }
        } else {
            let value = args[first.len()..].trim().trim_matches('"');
            env.insert(first.to_owned(), value.to_owned());
        }
    }
    env
}

fn only<'a>(stage: &[&'a Instruction], keyword: &str) -> &'a Instruction {
    let found: Vec<&&Instruction> = stage.iter().filter(|i| i.keyword == keyword).collect();
    assert_eq!(
        found.len(),
        1,
        "deploy/Dockerfile's final stage should have exactly one {keyword}, has {}",
        found.len()
    );
    found[0]
}

/// The numeric user id of a `USER uid[:gid]`; names are refused, since Kubernetes' runAsNonRoot
/// cannot check them.
fn numeric_uid(user: &Instruction) -> u64 {
    let uid = user.args.split(':').next().unwrap_or("");
    uid.parse().unwrap_or_else(|_| {
        panic!(
            "deploy/Dockerfile:{}: USER {:?} should be numeric so runAsNonRoot can verify it",
            user.line, user.args
        )
    })
}

// ---------------------------------------------------------------------------------------------
// The binary

/// The variables `scruple serve --help` lists as `[env: NAME...]`.
fn known_env() -> BTreeSet<String> {
    let output = support::scruple()
        .args(["serve", "--help"])
        .output()
        .expect("scruple serve --help runs");
    assert!(output.status.success(), "scruple serve --help failed: {output:?}");
    let help = String::from_utf8(output.stdout).expect("--help is UTF-8");
    let names: BTreeSet<String> = help
        .split("[env: ")
        .skip(1)
        .map(|rest| {
            rest.chars()
                .take_while(|c| c.is_ascii_uppercase() || c.is_ascii_digit() || *c == '_')
                .collect()
        })
        .collect();
    assert!(names.contains("SCRUPLE_LISTEN"), "no [env: ...] found in:\n{help}");
    names
}

/// Every `SCRUPLE_NAME` in a text, with its line number.
fn scruple_names(text: &str) -> Vec<(usize, String)> {
    let mut names = Vec::new();
    for (i, line) in text.lines().enumerate() {
        for (at, _) in line.match_indices("SCRUPLE_") {
            let name: String = line[at..]
                .chars()
                .take_while(|c| c.is_ascii_uppercase() || c.is_ascii_digit() || *c == '_')
                .collect();
            if name.len() > "SCRUPLE_".len() {
                names.push((i + 1, name));
            }
        }
    }
    names
}

/// A running `scruple serve`, killed when dropped so a failed assertion leaves no process behind.
struct Server {
    child: Child,
    addr: String,
}

impl Drop for Server {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// The real binary with the given environment, on a free port and a fresh SQLite file in `dir`
/// (the flags override the environment's listen address and store); its log goes to `dir/stderr`.
fn serve(env: &BTreeMap<String, String>, dir: &Path) -> Server {
    let log = dir.join("stderr");
    let mut command = support::scruple();
    command
        .args(["serve", "--listen", "127.0.0.1:0", "--database-url"])
        .arg(format!("sqlite://{}", dir.join("deploy.db").display()));
    let mut child = command
        .envs(env)
        .stdout(Stdio::piped())
        .stderr(std::fs::File::create(&log).expect("a log file"))
        .spawn()
        .expect("the binary starts");
    let stdout = child.stdout.take().unwrap();
    let mut server = Server {
        child,
        addr: String::new(),
    };
    let mut line = String::new();
    BufReader::new(stdout).read_line(&mut line).unwrap();
    server.addr = line
        .trim()
        .strip_prefix("listening on ")
        .unwrap_or_else(|| {
            let stderr = std::fs::read_to_string(&log).unwrap_or_default();
            panic!("scruple serve with the ConfigMap's and Secret's values did not start:\n{stderr}")
        })
        .to_owned();
    server
}

// ---------------------------------------------------------------------------------------------
// The checks

#[test]
fn every_scruple_variable_named_under_deploy_is_one_the_binary_reads() {
    let mut known = known_env();
    // And those the build reads (`build.rs` declares each), which an image build passes in.
    let build = read(&repo().join("build.rs"));
    for declared in build.split("rerun-if-env-changed=").skip(1) {
        known.insert(
            declared
                .chars()
                .take_while(|c| c.is_ascii_uppercase() || *c == '_')
                .collect(),
        );
    }
    let mut unknown = Vec::new();
    let mut checked = 0;
    for path in files_under(&repo().join("deploy")) {
        for (line, name) in scruple_names(&read(&path)) {
            checked += 1;
            if !known.contains(&name) {
                unknown.push(format!("{}:{line}: {name}", relative(&path)));
            }
        }
    }
    assert!(checked > 0, "no SCRUPLE_ variable found under deploy/");
    assert!(
        unknown.is_empty(),
        "these variables are not read by `scruple serve` (its --help lists {known:?}):\n{}",
        unknown.join("\n")
    );
}

#[test]
fn one_port_from_listen_through_expose_the_container_the_service_and_the_probes() {
    let objects = kustomized();
    let config = entries(the(&objects, "ConfigMap"));
    let listen = config.get("SCRUPLE_LISTEN").expect("the ConfigMap sets SCRUPLE_LISTEN");
    let port = port_of_listen(listen, "deploy/k8s ConfigMap");

    let docker = dockerfile();
    let runtime = final_stage(&docker);
    let docker_env = env_of(&runtime);
    let docker_listen = docker_env
        .get("SCRUPLE_LISTEN")
        .expect("deploy/Dockerfile's final stage sets ENV SCRUPLE_LISTEN");
    assert_eq!(
        port_of_listen(docker_listen, "deploy/Dockerfile"),
        port,
        "deploy/Dockerfile ENV SCRUPLE_LISTEN={docker_listen} but the ConfigMap says {listen}"
    );
    let expose = only(&runtime, "EXPOSE");
    assert_eq!(
        expose.args.trim_end_matches("/tcp"),
        port.to_string(),
        "deploy/Dockerfile:{}: EXPOSE {} but SCRUPLE_LISTEN is {listen}",
        expose.line,
        expose.args
    );

    let deployment = the(&objects, "Deployment");
    let container = container(deployment);
    let ports = container["ports"]
        .as_sequence()
        .expect("the container declares its ports");
    let http = ports
        .iter()
        .find(|p| p["name"].as_str() == Some("http"))
        .unwrap_or_else(|| panic!("{}: no container port named `http`", deployment.what()));
    let container_port = as_u64(&http["containerPort"], "the container port `http`");
    assert_eq!(
        container_port,
        u64::from(port),
        "{}: containerPort {container_port} but SCRUPLE_LISTEN is {listen}",
        deployment.what()
    );

    let service = the(&objects, "Service");
    let service_ports = service.doc["spec"]["ports"]
        .as_sequence()
        .expect("the Service has ports");
    for service_port in service_ports {
        assert_eq!(
            service_port["targetPort"].as_str(),
            Some("http"),
            "{}: targetPort {:?} should name the container port `http`, so the two cannot drift",
            service.what(),
            service_port["targetPort"]
        );
    }

    for probe in ["readinessProbe", "startupProbe", "livenessProbe"] {
        let target = &container[probe]["httpGet"]["port"];
        if !target.is_null() {
            assert_eq!(
                target.as_str(),
                Some("http"),
                "{}: {probe} port {target:?}",
                deployment.what()
            );
        }
    }
}

#[tokio::test]
async fn the_probes_answer_on_the_real_binary_run_with_the_deployed_settings() {
    let objects = kustomized();
    let deployment = the(&objects, "Deployment");
    let container = container(deployment);
    let path = |probe: &str| {
        container[probe]["httpGet"]["path"]
            .as_str()
            .unwrap_or_else(|| panic!("{}: {probe} is not an httpGet with a path", deployment.what()))
            .to_owned()
    };
    // Readiness follows the store; liveness only the process (a restart mends no store outage).
    let probes = [
        ("startupProbe", "/readyz"),
        ("readinessProbe", "/readyz"),
        ("livenessProbe", "/livez"),
    ];
    for (probe, expected) in probes {
        assert_eq!(path(probe), expected, "{}: {probe} path", deployment.what());
    }

    // Everything the pod gets from its ConfigMap and Secret, so a value the binary refuses fails here.
    let mut env = BTreeMap::new();
    for kind in ["ConfigMap", "Secret"] {
        env.extend(entries(the(&objects, kind)));
    }
    // The Secret's values are placeholders an operator replaces. The admin token's is refused as
    // it stands (under 16 bytes), so a deploy that forgets to replace it does not start with a
    // token anyone could guess; the run stands a token of the length asked in its place.
    let token = env.insert(
        "SCRUPLE_ADMIN_TOKEN".to_owned(),
        "a-stand-in-for-openssl-rand-hex-32".to_owned(),
    );
    assert!(
        token
            .as_deref()
            .is_some_and(|t| t.contains("REPLACE_ME") && t.len() < 16),
        "the Secret's admin token should be a placeholder the binary refuses: {token:?}"
    );
    let dir = tempfile::tempdir().unwrap();
    let server = serve(&env, dir.path());

    for (probe, _) in probes {
        let url = format!("http://{}{}", server.addr, path(probe));
        let response = support::http_client()
            .get(&url)
            .send()
            .await
            .unwrap_or_else(|e| panic!("{probe}: GET {url}: {e}"));
        assert_eq!(response.status(), reqwest::StatusCode::OK, "{probe}: GET {url}");
    }
}

#[test]
fn the_image_and_the_pod_run_as_the_same_non_root_numeric_user() {
    let docker = dockerfile();
    let runtime = final_stage(&docker);
    let user = only(&runtime, "USER");
    let uid = numeric_uid(user);
    assert_ne!(uid, 0, "deploy/Dockerfile:{}: USER is root", user.line);

    let objects = kustomized();
    let deployment = the(&objects, "Deployment");
    let pod = &deployment.doc["spec"]["template"]["spec"]["securityContext"];
    let own = &container(deployment)["securityContext"];
    let setting = |key: &str| if own[key].is_null() { &pod[key] } else { &own[key] };
    assert_eq!(
        setting("runAsNonRoot").as_bool(),
        Some(true),
        "{}: runAsNonRoot is not true",
        deployment.what()
    );
    if let Some(run_as) = setting("runAsUser").as_u64() {
        assert_eq!(
            run_as,
            uid,
            "{}: runAsUser {run_as} but deploy/Dockerfile:{} has USER {}",
            deployment.what(),
            user.line,
            user.args
        );
    }
    assert_eq!(
        own["readOnlyRootFilesystem"].as_bool(),
        Some(true),
        "{}: the root filesystem should be read-only",
        deployment.what()
    );
    let mounts = own_mounts(container(deployment));
    assert!(
        mounts.contains("/tmp"),
        "{}: a read-only root needs a writable /tmp (mounted: {mounts:?})",
        deployment.what()
    );
}

fn own_mounts(container: &Value) -> BTreeSet<String> {
    container["volumeMounts"]
        .as_sequence()
        .map(|mounts| {
            mounts
                .iter()
                .filter_map(|m| m["mountPath"].as_str().map(str::to_owned))
                .collect()
        })
        .unwrap_or_default()
}

#[test]
fn every_config_map_and_secret_key_the_pods_read_exists_and_every_key_is_read() {
    let objects = objects();
    let sources: BTreeMap<(&str, &str), (BTreeSet<String>, &Manifest)> = objects
        .iter()
        .filter(|m| matches!(m.kind(), "ConfigMap" | "Secret"))
        .map(|m| ((m.kind(), m.name()), (entries(m).into_keys().collect(), m)))
        .collect();
    let mut read = BTreeSet::<(&str, String, String)>::new();
    let mut problems = Vec::new();
    for workload in objects
        .iter()
        .filter(|m| matches!(m.kind(), "Deployment" | "StatefulSet"))
    {
        let containers = workload.doc["spec"]["template"]["spec"]["containers"]
            .as_sequence()
            .cloned()
            .unwrap_or_default();
        for container in &containers {
            for var in container["env"].as_sequence().cloned().unwrap_or_default() {
                let name = var["name"].as_str().unwrap_or("?");
                for (field, kind) in [("configMapKeyRef", "ConfigMap"), ("secretKeyRef", "Secret")] {
                    let reference = &var["valueFrom"][field];
                    if reference.is_null() {
                        continue;
                    }
                    let source = reference["name"].as_str().unwrap_or("");
                    let key = reference["key"].as_str().unwrap_or("");
                    read.insert((kind, source.to_owned(), key.to_owned()));
                    match sources.get(&(kind, source)) {
                        None => problems.push(format!(
                            "{}: {name} reads {kind} {source:?}, which no manifest under deploy/k8s defines",
                            workload.what()
                        )),
                        Some((keys, _)) if !keys.contains(key) => problems.push(format!(
                            "{}: {name} reads key {key:?} of {kind} {source:?}, which has only {keys:?}",
                            workload.what()
                        )),
                        Some(_) => {}
                    }
                }
            }
        }
    }
    for ((kind, source), (keys, manifest)) in &sources {
        for key in keys {
            if !read.contains(&(*kind, (*source).to_owned(), key.clone())) {
                problems.push(format!("{}: key {key:?} is read by no container", manifest.what()));
            }
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

/// The default of a `scruple serve` flag, as `--help` prints it (`[default: N]` after its
/// `[env: NAME=...]`).
fn default_of(env: &str) -> Option<String> {
    let output = support::scruple().args(["serve", "--help"]).output().unwrap();
    let help = String::from_utf8(output.stdout).unwrap();
    let at = help.find(&format!("[env: {env}"))?;
    let rest = &help[at..];
    let default = rest.split("[default: ").nth(1)?.split(']').next()?;
    Some(default.to_owned())
}

/// After SIGTERM the binary exits by its drain deadline, whatever clients do; Kubernetes SIGKILLs
/// at `terminationGracePeriodSeconds`. The deadline must come first, with room for the store to
/// close, or a slow client turns every rollout into a kill.
#[test]
fn the_drain_deadline_ends_well_inside_the_termination_grace_period() {
    let objects = kustomized();
    let deployment = the(&objects, "Deployment");
    let grace_s = deployment.doc["spec"]["template"]["spec"]["terminationGracePeriodSeconds"]
        .as_u64()
        // Kubernetes' default.
        .unwrap_or(30);
    let config = entries(the(&objects, "ConfigMap"));
    let drain_ms: u64 = config
        .get("SCRUPLE_DRAIN_TIMEOUT_MS")
        .cloned()
        .or_else(|| default_of("SCRUPLE_DRAIN_TIMEOUT_MS"))
        .expect("a drain deadline, from the ConfigMap or the binary's default")
        .parse()
        .expect("SCRUPLE_DRAIN_TIMEOUT_MS is a number");
    const ROOM_MS: u64 = 5_000;
    assert!(
        drain_ms + ROOM_MS <= grace_s * 1000,
        "{}: SCRUPLE_DRAIN_TIMEOUT_MS {drain_ms} leaves less than {ROOM_MS} ms of terminationGracePeriodSeconds {grace_s}",
        deployment.what()
    );
}

#[test]
fn secrets_hold_only_placeholders() {
    for secret in objects().iter().filter(|m| m.kind() == "Secret") {
        assert!(
            secret.doc["data"].is_null(),
            "{}: use stringData with REPLACE_ME placeholders, not base64 data",
            secret.what()
        );
        for (key, value) in entries(secret) {
            assert!(
                value.contains("REPLACE_ME"),
                "{}: {key} = {value:?} does not say REPLACE_ME; real secrets do not belong in the repository",
                secret.what()
            );
        }
    }
}

#[test]
fn the_service_autoscaler_and_disruption_budget_all_select_the_deployments_pods() {
    let objects = kustomized();
    let deployment = the(&objects, "Deployment");
    let labels = &deployment.doc["spec"]["template"]["metadata"]["labels"];
    let selects = |selector: &Value, whence: &str| {
        let selector = selector.as_mapping().unwrap_or_else(|| panic!("{whence}: no selector"));
        for (key, value) in selector {
            assert_eq!(
                &labels[key.as_str().unwrap()],
                value,
                "{whence}: selects {key:?}={value:?}, but the Deployment's pods are labelled {labels:?}"
            );
        }
    };
    selects(&deployment.doc["spec"]["selector"]["matchLabels"], &deployment.what());
    let service = the(&objects, "Service");
    selects(&service.doc["spec"]["selector"], &service.what());
    let pdb = the(&objects, "PodDisruptionBudget");
    selects(&pdb.doc["spec"]["selector"]["matchLabels"], &pdb.what());

    let hpa = the(&objects, "HorizontalPodAutoscaler");
    let target = &hpa.doc["spec"]["scaleTargetRef"];
    assert_eq!(
        (target["kind"].as_str(), target["name"].as_str()),
        (Some("Deployment"), Some(deployment.name())),
        "{}: scales {target:?}",
        hpa.what()
    );
    let min = as_u64(&hpa.doc["spec"]["minReplicas"], "the HPA's minReplicas");
    let min_available = as_u64(&pdb.doc["spec"]["minAvailable"], "the PDB's minAvailable");
    assert!(
        min_available < min,
        "{}: minAvailable {min_available} with as few as {min} replicas would block every node drain",
        pdb.what()
    );
    let requests = &container(deployment)["resources"]["requests"]["cpu"];
    assert!(
        !requests.is_null(),
        "{}: the HPA scales on CPU utilisation, which needs a CPU request",
        deployment.what()
    );
}

#[test]
fn the_kustomization_lists_every_manifest_but_the_postgres_example() {
    let kustomization = all_documents()
        .into_iter()
        .find(|m| m.kind() == "Kustomization")
        .expect("deploy/k8s/kustomization.yaml");
    let listed: BTreeSet<String> = kustomization.doc["resources"]
        .as_sequence()
        .expect("the kustomization lists resources")
        .iter()
        .map(|r| r.as_str().expect("a resource is a file name").to_owned())
        .collect();
    let present: BTreeSet<String> = yaml_files()
        .iter()
        .map(|p| p.strip_prefix(k8s_dir()).unwrap().display().to_string())
        .filter(|f| f != "kustomization.yaml" && f != POSTGRES_EXAMPLE)
        .collect();
    assert!(
        !listed.contains(POSTGRES_EXAMPLE),
        "deploy/k8s/kustomization.yaml lists {POSTGRES_EXAMPLE}, which is an example to apply by hand"
    );
    let missing: Vec<_> = present.difference(&listed).collect();
    let dangling: Vec<_> = listed.difference(&present).collect();
    assert!(
        missing.is_empty() && dangling.is_empty(),
        "deploy/k8s/kustomization.yaml does not list {missing:?}, and lists {dangling:?} which do not exist"
    );
}

#[test]
fn the_image_builds_the_locked_binary_with_a_new_enough_toolchain_and_runs_serve() {
    let docker = dockerfile();
    let builder = docker.iter().find(|i| i.keyword == "FROM").unwrap();
    let image = builder.args.split_whitespace().next().unwrap();
    let version = image.strip_prefix("rust:").unwrap_or_else(|| {
        panic!(
            "deploy/Dockerfile:{}: the builder {image} is not a rust image",
            builder.line
        )
    });
    let numbers = |v: &str| -> Vec<u64> { v.split(['.', '-']).map_while(|n| n.parse().ok()).collect() };
    let required = numbers(env!("CARGO_PKG_RUST_VERSION"));
    let pinned = numbers(version);
    // `rust:1-...` floats on the newest 1.x, which is new enough by definition.
    if pinned.len() > 1 {
        assert!(
            pinned >= required,
            "deploy/Dockerfile:{}: {image} is older than Cargo.toml's rust-version {}",
            builder.line,
            env!("CARGO_PKG_RUST_VERSION")
        );
    }
    assert!(
        docker.iter().any(|i| i.keyword == "RUN"
            && i.stage == builder.stage
            && i.args.contains("scripts/pgo-build.sh /out/scruple")),
        "deploy/Dockerfile: the builder should run `scripts/pgo-build.sh /out/scruple` (the profile-guided build)"
    );
    let script = read(&repo().join("scripts/pgo-build.sh"));
    assert_eq!(
        script
            .matches("cargo build --release --locked --quiet --bin scruple")
            .count(),
        2,
        "scripts/pgo-build.sh should build the locked server twice (instrumented, then optimised)"
    );
    // What the script reads beyond the build's sources must be copied into the builder (the check
    // below keeps `.dockerignore` from leaving it out of the context).
    for needed in [
        "scripts/pgo-build.sh",
        "scripts/lib.sh",
        "examples/grpc_body.rs",
        "tests/golden/corpus.jsonl",
    ] {
        assert!(
            docker
                .iter()
                .filter(|i| i.keyword == "COPY" && i.stage == builder.stage)
                .flat_map(copy_sources)
                .any(|source| within(needed, source)),
            "deploy/Dockerfile: the builder does not copy {needed}, which the profile-guided build needs"
        );
    }

    let runtime = final_stage(&docker);
    let entrypoint = only(&runtime, "ENTRYPOINT");
    assert_eq!(
        entrypoint.args, r#"["/usr/local/bin/scruple"]"#,
        "deploy/Dockerfile:{}",
        entrypoint.line
    );
    assert!(
        runtime
            .iter()
            .any(|i| i.keyword == "COPY" && i.args.ends_with(" /usr/local/bin/scruple")),
        "deploy/Dockerfile: the final stage does not copy the binary to /usr/local/bin/scruple"
    );
    let cmd = only(&runtime, "CMD");
    assert_eq!(cmd.args, r#"["serve"]"#, "deploy/Dockerfile:{}", cmd.line);
    let objects = kustomized();
    let deployment_args = &container(the(&objects, "Deployment"))["args"];
    if let Some(args) = deployment_args.as_sequence() {
        assert_eq!(
            args.first().and_then(Value::as_str),
            Some("serve"),
            "the Deployment's args"
        );
    }

    // What the builder copies must exist and must not be cut from the context by .dockerignore,
    // where the last line naming a path or a folder above it wins, and `!` lets it back in.
    let ignore: Vec<(bool, String)> = read(&repo().join(".dockerignore"))
        .lines()
        .map(str::trim)
        .filter(|l| !l.is_empty() && !l.starts_with('#'))
        .map(|l| match l.strip_prefix('!') {
            Some(back) => (false, back.trim_end_matches('/').to_owned()),
            None => (true, l.trim_end_matches('/').to_owned()),
        })
        .collect();
    let ignored = |source: &str| {
        ignore
            .iter()
            .rev()
            .find(|(_, p)| within(source, p))
            .is_some_and(|(out, _)| *out)
    };
    for copy in docker
        .iter()
        .filter(|i| i.keyword == "COPY" && !i.args.contains("--from"))
    {
        for source in copy_sources(copy) {
            assert!(
                repo().join(source).exists(),
                "deploy/Dockerfile:{}: COPY {source}, which is not in the repository",
                copy.line
            );
            assert!(
                !ignored(source),
                "deploy/Dockerfile:{}: COPY {source}, which .dockerignore leaves out of the build context",
                copy.line
            );
        }
    }

    // The SQLite default must live in the volume the image declares.
    let env = env_of(&runtime);
    let volume = only(&runtime, "VOLUME");
    if let Some(url) = env.get("SCRUPLE_DATABASE_URL") {
        let path = url.strip_prefix("sqlite://").unwrap_or("");
        assert!(
            path.starts_with(&format!("{}/", volume.args.trim_matches(['[', ']', '"']))),
            "deploy/Dockerfile: SCRUPLE_DATABASE_URL={url} is not inside VOLUME {}",
            volume.args
        );
    }
}

/// The `cargo test` command in `text`: its first line that starts with one, without a trailing
/// comment.
fn test_command(text: &str) -> Option<String> {
    text.lines()
        .map(|line| line.split('#').next().unwrap_or("").trim())
        .find(|command| command.starts_with("cargo test"))
        .map(str::to_owned)
}

/// The README's opening test command is what CI runs, so that a newcomer who runs it gets what
/// CI checks (`--locked`: the tests run against the committed `Cargo.lock`, not a fresh resolve).
#[test]
fn ci_runs_the_test_command_the_readme_opens_with() {
    let readme = read(&repo().join("README.md"));
    let opening: String = readme
        .split("```")
        .nth(1)
        .expect("README opens with a code block")
        .to_owned();
    let readme_command = test_command(&opening).expect("a cargo test command in the README's first block");
    let ci_command = test_command(&read(&repo().join(".ci/run"))).expect("a cargo test command in .ci/run");
    assert_eq!(ci_command, readme_command, "README.md and .ci/run");
    assert!(
        ci_command.split_whitespace().any(|word| word == "--locked"),
        "{ci_command}"
    );
}

// A conversation in the playground, in a real browser, against two running scruples on empty
// databases. On the first: the three-turn dialogue ("Get the mug." asks, "the red one" answers
// it as the contract's `answer`, "Put it in the sink." acts on the mug the answer put in focus),
// a screenshot of it, export and reload of the transcript (and a bad file refused whole), a
// reading chosen by its button, a task's steps, the focus cleared, people, speaker roles and
// context edited, and a verb edited and refused naming its field. On the second, started with a
// reader token and an admin token: the token goes on every request, reads included.
//
// Usage: node dialogue.mjs URL [SCREENSHOT] TOKEN_URL   (or SCRUPLE_URL, DIALOGUE_SCREENSHOT,
// SCRUPLE_TOKEN_URL). TOKEN_URL's service runs with --reader-token r=$READER_TOKEN and
// --admin-token $ADMIN_TOKEN (defaults below, as scripts/browser-test.sh starts it).

import { mkdirSync, mkdtempSync, readFileSync, writeFileSync } from "node:fs";
import { tmpdir } from "node:os";
import { dirname, join, resolve } from "node:path";
import { fileURLToPath } from "node:url";
import { launch } from "./chromium.mjs";

const here = dirname(fileURLToPath(import.meta.url));
const repo = resolve(here, "../..");
const url = process.argv[2] ?? process.env.SCRUPLE_URL;
const screenshot = resolve(process.argv[3] ?? process.env.DIALOGUE_SCREENSHOT ?? resolve(repo, "docs/dialogue.png"));
const tokenUrl = process.argv[4] ?? process.env.SCRUPLE_TOKEN_URL;
const readerToken = process.env.READER_TOKEN ?? "0123456789abcdef0123";
const adminToken = process.env.ADMIN_TOKEN ?? "fedcba9876543210fedc";
if (!url || !tokenUrl) {
  console.error("usage: node dialogue.mjs URL [SCREENSHOT] TOKEN_URL");
  process.exit(2);
}
const scratch = mkdtempSync(join(tmpdir(), "scruple-dialogue-"));

let passed = 0;
let failed = 0;
function check(ok, what, detail = "") {
  if (ok) {
    passed++;
    console.log(`dialogue: ok: ${what}`);
  } else {
    failed++;
    console.log(`dialogue: FAIL: ${what}${detail ? `: ${detail}` : ""}`);
  }
}
const same = (a, b) => JSON.stringify(a) === JSON.stringify(b);

/** Console errors and failed responses of a page, to be judged at the end. */
function watch(page) {
  const seen = { errors: [], failures: [] };
  page.on("pageerror", (e) => seen.errors.push(String(e)));
  page.on("console", (m) => {
    if (m.type() === "error" && !m.text().startsWith("Failed to load resource")) seen.errors.push(m.text());
  });
  page.on("response", (r) => {
    if (r.status() >= 400) seen.failures.push(`${r.request().method()} ${new URL(r.url()).pathname} ${r.status()}`);
  });
  return seen;
}

const turnCount = (page) => page.locator("#transcript li.turn").count();

/** Says `words` in the conversation's box (Enter submits) and returns the clarify request sent. */
async function say(page, words) {
  const before = await turnCount(page);
  await page.getByLabel("You say").fill(words);
  const [request] = await Promise.all([
    page.waitForRequest((r) => r.method() === "POST" && new URL(r.url()).pathname === "/v1/clarify"),
    page.getByLabel("You say").press("Enter"),
  ]);
  await page.waitForFunction((n) => document.querySelectorAll("#transcript li.turn").length === n, before + 1);
  return JSON.parse(request.postData());
}

/** Clicks an answer button of the open question and returns the clarify request sent. */
async function click(page, name) {
  const before = await turnCount(page);
  const [request] = await Promise.all([
    page.waitForRequest((r) => r.method() === "POST" && new URL(r.url()).pathname === "/v1/clarify"),
    page.locator("#transcript .answer-buttons").getByRole("button", { name, exact: true }).click(),
  ]);
  await page.waitForFunction((n) => document.querySelectorAll("#transcript li.turn").length === n, before + 1);
  return JSON.parse(request.postData());
}

/** What the transcript shows of turn `i` (negative: from the end). */
function turn(page, i) {
  return page.evaluate((i) => {
    const all = document.querySelectorAll("#transcript li.turn");
    const li = all[i < 0 ? all.length + i : i];
    const text = (sel) => li.querySelector(sel)?.textContent ?? null;
    return {
      said: text(".turn-said"),
      decision: text(".turn-decision"),
      utterance: text(".turn-utterance"),
      goal: text(".turn-goal"),
      steps: [...li.querySelectorAll(".turn-steps li")].map((x) => x.textContent),
      task: text(".turn-task"),
      buttons: [...li.querySelectorAll(".answer-buttons button")].map((b) => b.textContent),
    };
  }, i);
}

async function download(page) {
  const [file] = await Promise.all([
    page.waitForEvent("download"),
    page.getByRole("button", { name: "Export transcript" }).click(),
  ]);
  const path = join(scratch, file.suggestedFilename());
  await file.saveAs(path);
  return { path, name: file.suggestedFilename(), doc: JSON.parse(readFileSync(path, "utf8")) };
}

/** Adds a norm through the page's form; `fields` by label. */
async function addNorm(page, kind, term, fields = {}) {
  const rows = await page.locator("#norms-body button[data-norm]").count();
  await page.getByLabel("Kind", { exact: true }).selectOption(kind);
  await page.locator("#norm-term").fill(term);
  for (const label of ["When", "Context", "Roles", "Exempt roles", "Note"]) {
    await page.locator("#norm-form").getByLabel(label, { exact: true }).fill(fields[label] ?? "");
  }
  await page.getByRole("button", { name: "Add norm" }).click();
  await page.waitForFunction((n) => document.querySelectorAll("#norms-body button[data-norm]").length === n, rows + 1);
}

const browser = await launch();
try {
  // -------------------------------------------------------------------------------------------
  // The service without tokens, at the size of a laptop screen.
  const context = await browser.newContext({ viewport: { width: 1280, height: 800 }, deviceScaleFactor: 1, acceptDownloads: true });
  const page = await context.newPage();
  page.setDefaultTimeout(10_000);
  const seen = watch(page);

  await page.goto(url, { waitUntil: "load" });
  await page.waitForSelector("body[data-ready=true]");
  await page.waitForSelector("#verbs-body button[data-verb]");

  check(
    await page.evaluate(() => document.documentElement.scrollWidth <= window.innerWidth),
    "no horizontal overflow at 1280x800",
    String(await page.evaluate(() => document.documentElement.scrollWidth)),
  );
  const unlabelled = await page.evaluate(() =>
    [...document.querySelectorAll("input, select, textarea")]
      .filter((el) => el.type !== "radio" || !el.closest("label"))
      .filter((el) => !el.labels?.length && !el.getAttribute("aria-label") && !el.getAttribute("aria-labelledby"))
      .map((el) => el.id || el.outerHTML.slice(0, 60)),
  );
  check(unlabelled.length === 0, "every input, select and textarea has a label", unlabelled.join(", "));

  await page.getByLabel("Preset", { exact: true }).selectOption("kitchen");
  await page.getByRole("button", { name: "Load scene" }).click();
  check(
    (await page.textContent("#scene-json-status")) === "Drawn: 4 objects, 1 person.",
    "the kitchen preset is drawn",
    await page.textContent("#scene-json-status"),
  );
  const kitchen = JSON.parse(await page.inputValue("#scene-json"));

  // Turn 1: "Get the mug." with two mugs and no norm: the robot asks which.
  const first = await say(page, "Get the mug.");
  let t = await turn(page, 0);
  check(
    t.decision === "ask" &&
      t.utterance === "Do you mean that you want me to get the blue mug or that you want me to get the red mug?",
    "turn 1: “Get the mug.” is asked about, naming both mugs",
    JSON.stringify(t),
  );
  check(
    same(t.buttons, ["the blue mug", "the red mug", "None of them"]),
    "turn 1: each offered reading is a button",
    JSON.stringify(t.buttons),
  );
  check(
    same(first.directive, { text: "Get the mug." }) && first.answer === undefined && first.focus === undefined,
    "turn 1 is sent as a directive in words, with no answer and nothing in focus",
    JSON.stringify(first),
  );
  check((await page.textContent("#say-hint")).includes("answers it"), "the box says the next words answer the question");

  // Turn 2: "the red one" is the answer: the question's request sent again with it.
  const second = await say(page, "the red one");
  t = await turn(page, 1);
  const { answer: secondAnswer, ...secondRest } = second;
  check(
    same(secondAnswer, { text: "the red one" }) && same(secondRest, first),
    "turn 2 is sent as the first request again with \"answer\": {\"text\": \"the red one\"}",
    JSON.stringify(second),
  );
  check(
    t.decision === "comply" && t.utterance === "Okay." && t.goal === "did(self,get(mug1))",
    "turn 2: the robot gets the red mug",
    JSON.stringify(t),
  );
  check((await page.inputValue("#focus")) === "mug1", "the red mug is in focus", await page.inputValue("#focus"));
  check((await page.locator("#transcript .answer-buttons").count()) === 0, "the question is closed: no answer buttons are left");

  // Turn 3: "Put it in the sink.": "it" is the mug the answer put in focus.
  const third = await say(page, "Put it in the sink.");
  t = await turn(page, 2);
  check(
    same(third.focus, ["mug1"]) && third.answer === undefined && same(third.directive, { text: "Put it in the sink." }),
    "turn 3 is a new directive carrying the focus [\"mug1\"]",
    JSON.stringify({ focus: third.focus, answer: third.answer, directive: third.directive }),
  );
  check(
    t.decision === "comply" && t.utterance === "Okay." && t.goal === "did(self,put(mug1,sink1))",
    "turn 3: the robot puts the red mug in the sink",
    JSON.stringify(t),
  );
  const dialogue = await page.evaluate(() =>
    [...document.querySelectorAll("#transcript li.turn")].map((li) => [
      li.querySelector(".turn-said").textContent,
      li.querySelector(".turn-decision").textContent,
      li.querySelector(".turn-utterance").textContent,
    ]),
  );
  check(
    same(dialogue, [
      ["Get the mug.", "ask", "Do you mean that you want me to get the blue mug or that you want me to get the red mug?"],
      ["the red one", "comply", "Okay."],
      ["Put it in the sink.", "comply", "Okay."],
    ]),
    "the transcript shows the three turns: what was said, each decision and utterance",
    JSON.stringify(dialogue),
  );
  check((await page.inputValue("#focus")) === "mug1, sink1", "the focus carries the mug, then the sink", await page.inputValue("#focus"));
  check((await page.textContent("#decision-kind")) === "comply", "the decision panel shows the last turn");
  const box = await page.locator("#transcript").boundingBox();
  check(box && box.y >= 0 && box.y + box.height <= 800, "the transcript is on screen at 1280x800", JSON.stringify(box));
  await page.evaluate(() => window.scrollTo(0, 0));
  mkdirSync(dirname(screenshot), { recursive: true });
  await page.screenshot({ path: screenshot });
  console.log(`dialogue: screenshot at ${screenshot}`);

  // Export, then reload: the same transcript, scene, focus and settings.
  const shown = await page.innerText("#transcript");
  const exported = await download(page);
  const doc = exported.doc;
  check(
    doc.format === "scruple-playground-transcript" && doc.version === 1 && doc.turns.length === 3 &&
      Number.isInteger(doc.norm_version) && Number.isInteger(doc.library_version) &&
      same(doc.scene, kitchen) && doc.settings.options.strategy === "moral" && same(doc.focus, ["mug1", "sink1"]) &&
      same(doc.turns[1].request.answer, { text: "the red one" }) && doc.turns[2].response.goal === "did(self,put(mug1,sink1))",
    "the exported file holds the turns, the scene, the norms version, the options and the focus",
    JSON.stringify({ ...doc, turns: doc.turns.length, scene: undefined }),
  );

  // A bad file is refused whole: the conversation stays as it was.
  const broken = structuredClone(doc);
  delete broken.turns[1].response.decision;
  writeFileSync(join(scratch, "broken.json"), JSON.stringify(broken));
  writeFileSync(join(scratch, "not-json.json"), "{ this is not json");
  await page.locator("#load-transcript").setInputFiles(join(scratch, "broken.json"));
  await page.waitForSelector("#transcript-error .problem");
  const brokenSaid = await page.textContent("#transcript-error");
  check(
    brokenSaid.includes("/turns/1/response/decision") && brokenSaid.includes("Not a transcript"),
    "a transcript missing a decision is refused, naming /turns/1/response/decision",
    brokenSaid,
  );
  check(
    (await page.innerText("#transcript")) === shown && (await page.inputValue("#focus")) === "mug1, sink1",
    "after the bad file the transcript and focus are as they were",
  );
  await page.locator("#load-transcript").setInputFiles(join(scratch, "not-json.json"));
  await page.waitForFunction(() => document.querySelector("#transcript-error").textContent.includes("not JSON"));
  check((await page.innerText("#transcript")) === shown, "a file that is not JSON is refused too, and nothing changes");

  await page.getByRole("button", { name: "New conversation" }).click();
  check(
    (await turnCount(page)) === 0 && (await page.inputValue("#focus")) === "",
    "“New conversation” clears the transcript and the focus",
  );
  await page.locator("#load-transcript").setInputFiles(exported.path);
  await page.waitForFunction(() => document.querySelectorAll("#transcript li.turn").length === 3);
  check((await page.innerText("#transcript")) === shown, "reloading the export shows the same transcript");
  check(
    (await page.inputValue("#focus")) === "mug1, sink1" && (await page.textContent("#transcript-error")) === "" &&
      (await page.textContent("#transcript-status")).startsWith("Loaded 3 turns"),
    "with its focus, and says what it loaded",
    await page.textContent("#transcript-status"),
  );
  const again = await download(page);
  check(
    same({ ...again.doc, exported_at: null }, { ...doc, exported_at: null }),
    "exported again, the file is the same but for its time",
  );

  // A task, asked about; a reading chosen by its button is the contract's {"choice": N}.
  await page.getByRole("button", { name: "New conversation" }).click();
  const task = await say(page, "Please take the mug and put it in the sink");
  t = await turn(page, -1);
  check(
    t.decision === "ask" && same(t.buttons, ["get the blue mug and put it in the sink", "get the red mug and put it in the sink", "None of them"]),
    "a task with two mugs is asked about, each whole task a button",
    JSON.stringify(t),
  );
  check(t.steps.length === 2 && t.steps[0].startsWith("get(X)") && t.steps[1].startsWith("put(X,Y)"), "the question shows the task's steps as read", JSON.stringify(t.steps));
  const chosen = await click(page, "get the red mug and put it in the sink");
  t = await turn(page, -1);
  check(
    same(chosen.answer, { choice: 1 }) && same({ ...chosen, answer: undefined }, { ...task, answer: undefined }),
    "clicking the second reading sends the task's request with \"answer\": {\"choice\": 1}",
    JSON.stringify(chosen.answer),
  );
  check(
    t.decision === "comply" && t.goal === "did(self,and(get(mug1),put(mug1,sink1)))" &&
      same(t.steps, ["get(mug1)", "put(mug1,sink1)"]) && t.task.includes("get(mug1) → get(mug1) → put(mug1,sink1)") &&
      t.said.includes("get the red mug and put it in the sink"),
    "the chosen task is done: its steps and plan are shown",
    JSON.stringify(t),
  );

  // "None of them" takes the question back.
  await say(page, "Get the mug.");
  const none = await click(page, "None of them");
  t = await turn(page, -1);
  check(
    same(none.answer, { text: "none of them" }) && t.decision === "cancelled" && t.utterance === "Okay, I will not.",
    "“None of them” answers in words and the robot does nothing",
    JSON.stringify(t),
  );

  // The focus cleared: "it" means nothing.
  await page.getByRole("button", { name: "Clear focus" }).click();
  check((await page.inputValue("#focus")) === "", "“Clear focus” empties it");
  const it = await say(page, "Get it.");
  t = await turn(page, -1);
  check(
    it.focus === undefined && t.decision === "unresolved" && t.utterance === "I do not know what you mean by it.",
    "with no focus, “Get it.” is sent without one and is unresolved",
    JSON.stringify(t),
  );

  // People, edited in the page: Bob is a child, and then a parent.
  await addNorm(page, "forbidden_action", "give(X,P)", { When: "role(P,child)" });
  await say(page, "Give the red mug to Bob.");
  t = await turn(page, -1);
  check(
    t.decision === "refuse" &&
      t.utterance === "I cannot give the red mug to Bob because giving the red mug to Bob is forbidden when Bob is a child.",
    "Bob, a child, may not be given the mug",
    JSON.stringify(t),
  );
  await page.locator("#people-editor > summary").click();
  await page.getByLabel("Person 1 roles").fill("parent");
  await page.waitForFunction(() => JSON.parse(document.querySelector("#scene-json").value).people[0].roles[0] === "parent");
  const bobAgain = await say(page, "Give the red mug to Bob.");
  t = await turn(page, -1);
  check(
    same(bobAgain.scene.people[0].roles, ["parent"]) && t.decision === "comply" && t.goal === "did(self,give(mug1,bob))",
    "Bob's role edited to parent: the scene sent says so, and the mug is given",
    JSON.stringify(t),
  );
  await page.getByRole("button", { name: "Add a person" }).click();
  await page.getByLabel("Person 2 id").fill("alice");
  await page.getByLabel("Person 2 names").fill("Alice");
  await page.getByLabel("Person 2 roles").fill("child");
  await page.getByLabel("Person 2 position").fill("0.7, -0.6, 0.8");
  await page.waitForFunction(() => {
    const alice = JSON.parse(document.querySelector("#scene-json").value).people[1];
    return alice?.id === "alice" && alice.names?.[0] === "Alice" && alice.roles?.[0] === "child" && alice.position[1] === -0.6;
  });
  check((await page.locator("#scene-svg .person-shape").count()) === 2, "a person added in the page is drawn");
  await say(page, "Give the blue mug to Alice.");
  t = await turn(page, -1);
  check(
    t.decision === "refuse" && t.utterance.includes("forbidden when Alice is a child"),
    "and is a person to the service: Alice, a child, may not be given the mug",
    t.utterance,
  );
  await page.getByLabel("Person 2 position").fill("0.7, -0.6");
  await page.waitForFunction(() => document.querySelector("#people-status").textContent.startsWith("Not written"));
  check(
    (await page.getByLabel("Person 2 position").getAttribute("aria-invalid")) === "true" &&
      (await page.textContent("#scene-json-status")) === "Drawn: 4 objects, 2 people.",
    "a position of two numbers is marked and not written to the scene",
  );
  await page.getByRole("button", { name: "Remove person 2 (alice)" }).click();
  check((await page.textContent("#scene-json-status")) === "Drawn: 4 objects, 1 person.", "a person removed leaves the scene");

  // Speaker roles and context select the norms in force.
  await addNorm(page, "forbidden_action", "discard", { Roles: "guest" });
  await addNorm(page, "forbidden_action", "pour", { Context: "hospital" });
  await page.getByLabel("Speaker roles").fill("guest");
  const guest = await say(page, "Throw away the red mug.");
  t = await turn(page, -1);
  check(
    same(guest.speaker_roles, ["guest"]) && t.decision === "refuse",
    "a guest may not throw the mug away (speaker_roles sent)",
    JSON.stringify({ roles: guest.speaker_roles, t }),
  );
  await page.getByLabel("Speaker roles").fill("");
  const host = await say(page, "Throw away the red mug.");
  t = await turn(page, -1);
  check(host.speaker_roles === undefined && t.decision === "comply", "with no role, the same words are obeyed", JSON.stringify(t));
  await page.locator("#clarify-form").getByLabel("Context", { exact: true }).fill("hospital");
  const ward = await say(page, "Pour the red mug into the sink.");
  t = await turn(page, -1);
  check(
    ward.context === "hospital" && t.decision === "refuse" && t.utterance.includes("hospital"),
    "in the hospital context pouring is refused",
    JSON.stringify(t),
  );
  await page.locator("#clarify-form").getByLabel("Context", { exact: true }).fill("default");
  await page.getByLabel("Speaker", { exact: true }).fill("bob");
  const me = await say(page, "Pour the red mug into the sink.");
  t = await turn(page, -1);
  check(me.speaker === "bob" && t.decision === "comply", "elsewhere it is obeyed, and the speaker is sent", JSON.stringify(t));
  await page.getByLabel("Speaker", { exact: true }).fill("human");

  // Verbs: listed from GET /v1/actions, edited as JSON, refused naming the field.
  const listed = await page.locator("#verbs-body tr").allTextContents();
  check(
    listed.some((r) => r.startsWith("get(X)")) && listed.some((r) => r.startsWith("put(X,Y)")) && listed.some((r) => r.startsWith("give(X,P)")),
    "the stored verbs are listed with their parameters",
    listed.join(" | "),
  );
  await page.getByRole("button", { name: "Edit verb open" }).click();
  check(
    (await page.inputValue("#verb-name")) === "open" && (await page.inputValue("#verb-json")).includes("closed(X)"),
    "a verb is opened for editing as JSON",
  );
  await page.getByLabel("Verb JSON").fill('{"parameters": ["X"], "methods": [{"reach": ["Z"], "adds": ["open(X)"]}]}');
  await page.getByRole("button", { name: "Save verb" }).click();
  await page.waitForSelector("#verb-error .problem");
  const verbProblem = await page.textContent("#verb-error");
  check(
    verbProblem.includes("/methods/0/reach/0") && verbProblem.includes("`Z` is not a parameter") && verbProblem.includes('There: "Z"'),
    "a bad verb is refused: the problem names /methods/0/reach/0 and shows what is there",
    verbProblem,
  );
  check((await page.getByLabel("Verb JSON").getAttribute("aria-invalid")) === "true", "the verb's JSON is marked invalid");
  await page.getByLabel("Verb name").fill("Shake");
  await page.getByLabel("Verb JSON").fill('{"parameters": ["X"], "methods": [{"reach": ["X"]}], "words": ["shake"]}');
  await page.getByRole("button", { name: "Save verb" }).click();
  await page.waitForFunction(() => document.querySelector("#verb-error").textContent.includes("/name"));
  check((await page.getByLabel("Verb name").getAttribute("aria-invalid")) === "true", "a verb name the service refuses marks the name (/name)");
  await page.getByLabel("Verb name").fill("shake");
  await page.getByLabel("Verb JSON").press("Control+Enter");
  await page.waitForFunction(() => document.querySelector("#verbs-status").textContent === "Saved verb shake.");
  check(
    (await page.locator("#verbs-body tr", { hasText: "shake(X)" }).count()) === 1 && (await page.textContent("#verb-error")) === "",
    "a good verb is saved (Ctrl+Enter) and listed",
  );
  await say(page, "Shake the red mug.");
  t = await turn(page, -1);
  check(t.decision === "comply" && t.goal === "did(self,shake(mug1))", "and the robot understands the new verb at once", JSON.stringify(t));

  // The directive form's words, while a question is open, answer it too.
  await say(page, "Get the mug.");
  await page.getByLabel("the words only").check();
  await page.getByLabel("Human's words").fill("the blue one");
  const [formAnswer] = await Promise.all([
    page.waitForRequest((r) => r.method() === "POST" && new URL(r.url()).pathname === "/v1/clarify"),
    page.getByRole("button", { name: "Ask Scruple" }).click(),
  ]);
  await page.waitForFunction(() => document.querySelector("#transcript li.turn:last-child .turn-said")?.textContent === "the blue one");
  t = await turn(page, -1);
  check(
    same(JSON.parse(formAnswer.postData()).answer, { text: "the blue one" }) && t.goal === "did(self,get(mug2))",
    "words from the directive form answer the open question as well",
    JSON.stringify(t),
  );

  // A confirmation answered "Yes" by its button, and an alternative taken from the transcript.
  await addNorm(page, "forbidden_action", "get(X)", { When: "color(X,red)" });
  await page.getByLabel("One permissible reading").selectOption("confirm");
  await say(page, "Get the mug.");
  t = await turn(page, -1);
  check(
    t.decision === "confirm" && t.utterance.startsWith("Do you want me to get the blue mug?") && same(t.buttons, ["Yes, the blue mug", "No"]),
    "with the red mug forbidden, the robot confirms the blue one: Yes and No buttons",
    JSON.stringify(t),
  );
  const yes = await click(page, "Yes, the blue mug");
  t = await turn(page, -1);
  check(same(yes.answer, { choice: 0 }) && t.goal === "did(self,get(mug2))", "“Yes” is {\"choice\": 0}: the blue mug is got", JSON.stringify(t));
  await page.getByLabel("One permissible reading").selectOption("assume");
  await page.getByLabel("Style", { exact: true }).selectOption("natural");
  await say(page, "Get the red mug.");
  t = await turn(page, -1);
  check(
    t.decision === "refuse" && t.utterance.endsWith("Shall I get the blue mug instead?") && t.buttons.includes("Yes, take the alternative"),
    "a refusal offering the blue mug instead has a button to take it",
    JSON.stringify(t),
  );
  const alternative = await click(page, "Yes, take the alternative");
  t = await turn(page, -1);
  check(
    same(alternative.answer, { choice: "alternative" }) && t.decision === "comply" && t.goal === "did(self,get(mug2))",
    "taking it sends {\"choice\": \"alternative\"} and the blue mug is got",
    JSON.stringify(t),
  );
  await page.getByLabel("Style", { exact: true }).selectOption("diarc");

  const scroll = await page.evaluate(() => {
    const el = document.querySelector("#transcript");
    return { overflow: getComputedStyle(el).overflowY, scroll: el.scrollHeight, client: el.clientHeight, top: el.scrollTop };
  });
  check(
    scroll.overflow === "auto" && scroll.scroll > scroll.client && scroll.top + scroll.client >= scroll.scroll - 2,
    "a long transcript scrolls, kept at its latest turn",
    JSON.stringify(scroll),
  );
  check(
    await page.evaluate(() => document.documentElement.scrollWidth <= window.innerWidth),
    "still no horizontal overflow after the whole conversation",
  );
  check(seen.errors.length === 0, "no console or page errors (CSP included)", seen.errors.join(" | "));
  check(
    same(seen.failures, ["PUT /v1/actions/open 422", "PUT /v1/actions/Shake 422"]),
    "no request failed but the two refused verbs",
    seen.failures.join(" | "),
  );
  await context.close();

  // -------------------------------------------------------------------------------------------
  // A service with reader tokens: without one the page cannot read; with one, every request
  // carries it, reads included; a reader cannot write, an admin can.
  const tokenContext = await browser.newContext({ viewport: { width: 1280, height: 800 }, deviceScaleFactor: 1 });
  const tp = await tokenContext.newPage();
  tp.setDefaultTimeout(10_000);
  const tseen = watch(tp);
  // Each request to the service, with the token the page was given when it was sent.
  const sent = [];
  let given = null;
  tp.on("request", (r) => {
    const path = new URL(r.url()).pathname;
    if (path.startsWith("/v1/") || path === "/healthz") {
      sent.push({ method: r.method(), path, given, headers: r.allHeaders() });
    }
  });
  await tp.goto(tokenUrl, { waitUntil: "load" });
  await tp.waitForSelector("body[data-ready=true]");
  await tp.waitForFunction(() => document.querySelector("#norm-error").textContent.includes("401"));
  check(
    (await tp.textContent("#norm-error")).includes("Unauthenticated") && (await tp.textContent("#verb-error")).includes("401"),
    "without a token a reader-token service refuses the norms and verbs, and the page says so",
  );
  given = readerToken;
  await tp.getByLabel("Token", { exact: true }).fill(readerToken);
  await tp.getByLabel("Token", { exact: true }).press("Enter");
  await tp.waitForFunction(() => document.querySelectorAll("#verbs-body button[data-verb]").length > 5);
  await tp.waitForFunction(() => document.querySelector("#norms-body td.empty"));
  check(
    (await tp.textContent("#norm-error")) === "" && (await tp.textContent("#verb-error")) === "",
    "with the reader token the norms and verbs are read, and the problems go",
  );
  await tp.getByLabel("Preset", { exact: true }).selectOption("kitchen");
  await tp.getByRole("button", { name: "Load scene" }).click();
  await say(tp, "Get the mug.");
  await click(tp, "the red mug");
  check((await turn(tp, -1)).goal === "did(self,get(mug1))", "the conversation works with the token");
  await tp.getByRole("button", { name: "Edit verb open" }).click();
  await tp.getByRole("button", { name: "Save verb" }).click();
  await tp.waitForFunction(() => document.querySelector("#verb-error").textContent.includes("403"));
  check((await tp.textContent("#verb-error")).includes("Forbidden"), "a reader's token cannot save a verb: the 403 is shown", await tp.textContent("#verb-error"));
  given = adminToken;
  await tp.getByLabel("Token", { exact: true }).fill(adminToken);
  await tp.getByLabel("Token", { exact: true }).press("Enter");
  await tp.getByRole("button", { name: "Save verb" }).click();
  await tp.waitForFunction(() => document.querySelector("#verbs-status").textContent === "Saved verb open.");
  check((await tp.textContent("#verb-error")) === "", "an admin's token saves it");
  await tp.waitForTimeout(500);
  for (const s of sent) s.authorization = (await s.headers).authorization ?? null;
  const kinds = (token) => new Set(sent.filter((s) => s.given === token).map((s) => `${s.method} ${s.path}`));
  const read = ["GET /healthz", "GET /v1/norms", "GET /v1/actions"];
  check(
    [...read, "POST /v1/clarify", "PUT /v1/actions/open"].every((k) => kinds(readerToken).has(k)) &&
      [...read, "PUT /v1/actions/open"].every((k) => kinds(adminToken).has(k)),
    "with each token the page read health, norms and verbs, and asked or wrote",
    JSON.stringify([[...kinds(readerToken)], [...kinds(adminToken)]]),
  );
  const wrong = sent.filter((s) => s.authorization !== (s.given ? `Bearer ${s.given}` : null));
  check(
    wrong.length === 0 && sent.filter((s) => s.given === null).length >= 3,
    "every request carried the token given, GETs included (Authorization: Bearer …), and none before it",
    JSON.stringify(wrong.map(({ headers, ...s }) => s)),
  );
  check(tseen.errors.length === 0, "no console or page errors with tokens", tseen.errors.join(" | "));
  check(
    same(tseen.failures.sort(), ["GET /v1/actions 401", "GET /v1/norms 401", "PUT /v1/actions/open 403"]),
    "no request failed but the reads before the token and the reader's write",
    tseen.failures.join(" | "),
  );
  await tokenContext.close();
} catch (e) {
  check(false, "the run finished", e.stack ?? String(e));
} finally {
  await browser.close();
}
console.log(`dialogue: ${passed} passed, ${failed} failed`);
process.exit(failed === 0 ? 0 : 1);

// The playground in a real browser, against a running scruple on an empty database:
// load the paper's lab, install the paper's norms through the page's norm form, say
// "Get the vase." and expect the paper's exact assume utterance; then save a screenshot.
//
// Usage: node playground.mjs URL [SCREENSHOT]   (or SCRUPLE_URL, SCREENSHOT)
// PAPER_DEMO names the scenario file (default: ../shared/scenarios/paper-demo.json beside the repo).

import { readFileSync, mkdirSync } from "node:fs";
import { dirname, resolve } from "node:path";
import { fileURLToPath } from "node:url";
import { launch } from "./chromium.mjs";

const here = dirname(fileURLToPath(import.meta.url));
const repo = resolve(here, "../..");
const url = process.argv[2] ?? process.env.SCRUPLE_URL;
const screenshot = resolve(process.argv[3] ?? process.env.SCREENSHOT ?? resolve(repo, "docs/playground.png"));
const demoPath = process.env.PAPER_DEMO ?? resolve(repo, "../shared/scenarios/paper-demo.json");
if (!url) {
  console.error("usage: node playground.mjs URL [SCREENSHOT]");
  process.exit(2);
}

const demo = JSON.parse(readFileSync(demoPath, "utf8"));
const vaseCase = demo.cases.find((c) => c.scene === "lab" && c.text === "Get the vase." && c.directive.action && !c.options);
if (!vaseCase) throw new Error(`no plain "Get the vase." case in ${demoPath}`);
const expected = vaseCase.expect.utterance;

let passed = 0;
let failed = 0;
function check(ok, what, detail = "") {
  if (ok) {
    passed++;
    console.log(`browser: ok: ${what}`);
  } else {
    failed++;
    console.log(`browser: FAIL: ${what}${detail ? `: ${detail}` : ""}`);
  }
}

const browser = await launch();
try {
  const context = await browser.newContext({ viewport: { width: 1440, height: 900 }, deviceScaleFactor: 1 });
  const page = await context.newPage();
  page.setDefaultTimeout(10_000);
  // Console errors include CSP violations: the page must load nothing it does not serve itself.
  const pageErrors = [];
  page.on("pageerror", (e) => pageErrors.push(String(e)));
  // Failed loads are judged by their responses below, where the one refusal we provoke is known.
  page.on("console", (m) => {
    if (m.type() === "error" && !m.text().startsWith("Failed to load resource")) pageErrors.push(m.text());
  });
  const failedResponses = [];
  page.on("response", (r) => {
    if (r.status() >= 400) failedResponses.push(`${r.request().method()} ${new URL(r.url()).pathname} ${r.status()}`);
  });

  const response = await page.goto(url, { waitUntil: "load" });
  check(response?.status() === 200, "GET / is 200", String(response?.status()));
  await page.waitForSelector("body[data-ready=true]");
  await page.waitForSelector("#norms-body tr");
  check((await page.textContent("#health")) === "ok", "the page reports the service healthy");

  // The scene: the paper's lab, drawn.
  await page.getByLabel("Preset", { exact: true }).selectOption("lab");
  await page.getByRole("button", { name: "Load scene" }).click();
  const drawn = await page.locator("#scene-svg").textContent();
  for (const label of ["red notebook", "green notebook", "fragile vase", "plastic vase", "mug", "object3", "object4"]) {
    check(drawn.includes(label), `the drawing labels ${label}`);
  }

  // A bad norm is refused and the problem is shown readably, naming the field.
  await page.getByLabel("Kind", { exact: true }).selectOption("forbidden_action");
  await page.locator("#norm-term").fill("destroy");
  await page.getByLabel("Severity", { exact: true }).fill("9");
  await page.getByRole("button", { name: "Add norm" }).click();
  const problem = page.locator("#norm-error .problem");
  await problem.waitFor();
  const problemText = await problem.textContent();
  check(problemText.includes("/severity"), "a severity of 9 is shown as a problem naming /severity", problemText);
  check(
    (await page.getByLabel("Severity", { exact: true }).getAttribute("aria-invalid")) === "true",
    "the severity control is marked invalid",
  );
  await page.getByLabel("Severity", { exact: true }).fill("3");

  // The paper's norms, in its order, through the page's form.
  for (const [i, norm] of demo.norms.entries()) {
    await page.getByLabel("Kind", { exact: true }).selectOption(norm.kind);
    await page.locator("#norm-term").fill(norm.action ?? norm.state);
    await page.getByLabel("Note", { exact: true }).fill(norm.note ?? "");
    await page.getByRole("button", { name: "Add norm" }).click();
    await page.waitForFunction((n) => document.querySelectorAll("#norms-body button[data-norm]").length === n, i + 1);
  }
  const rows = await page.locator("#norms-body tr").allTextContents();
  check(rows.length === demo.norms.length, `the table lists the paper's ${demo.norms.length} norms`, rows.join(" | "));
  check(rows.some((r) => r.includes("did(self,get(object3))")), "the forbidden state did(self,get(object3)) is listed");
  check((await page.locator("#norm-error").textContent()) === "", "no problem is left on the norm form");

  // "Get the vase.", typed and submitted from the keyboard.
  await page.getByLabel("Human's words").fill(vaseCase.text);
  await page.getByLabel("a verb and references").check();
  await page.getByLabel("Verb", { exact: true }).fill(vaseCase.directive.action);
  await page.locator("#ref1-type").fill(vaseCase.directive.arguments[0].type);
  await page.locator("#ref1-type").press("Enter");
  const utterance = page.locator("#utterance");
  await utterance.waitFor();
  await page.waitForFunction(
    (want) => document.querySelector("#utterance")?.textContent.endsWith(want),
    expected,
  );
  const said = await utterance.textContent();
  check(said.endsWith(expected), `the robot says the paper's words: "${expected}"`, said);
  check((await page.textContent("#decision-kind")) === vaseCase.expect.decision, `the decision is ${vaseCase.expect.decision}`);
  check(
    (await page.locator("#decision").getAttribute("aria-live")) === "polite",
    "the decision is announced (aria-live)",
  );
  const forbidden = await page.locator("#readings li.reading.forbidden").allTextContents();
  const ok = await page.locator("#readings li.reading.ok").allTextContents();
  check(forbidden.length === 1 && forbidden[0].includes("the fragile vase"), "the fragile vase reading is forbidden", forbidden.join());
  check(forbidden[0]?.includes("it requires a forbidden state"), "its reason is spoken", forbidden.join());
  check(ok.length === 1 && ok[0].includes("the plastic vase"), "the plastic vase reading is permissible", ok.join());
  check(
    (await page.locator("#scene-svg g.obj.forbidden").count()) === 1 &&
      (await page.locator("#scene-svg g.obj.ok.chosen").count()) === 1,
    "the drawing colours the forbidden vase and the chosen one",
  );
  // The same case in the words only: the same decision, and the parse shown.
  await page.getByLabel("the words only").check();
  await page.getByLabel("Human's words").fill(vaseCase.text);
  await page.getByLabel("Human's words").press("Enter");
  await page.waitForSelector("#parse-form");
  check(
    (await page.textContent("#parse-form")) === "want(human,did(self,get(X)))",
    "the words only: the parse shows want(human,did(self,get(X)))",
    await page.textContent("#parse-form"),
  );
  check((await page.textContent("#utterance")).endsWith(expected), "the words only: the paper's words again");

  // A soft norm, added through the form: the red notebook is still permissible, but outranked.
  await page.getByLabel("Kind", { exact: true }).selectOption("discouraged_action");
  await page.locator("#norm-term").fill("get(X)");
  await page.getByLabel("When", { exact: true }).fill("color(X,red)");
  await page.getByLabel("Severity", { exact: true }).fill("2");
  await page.getByRole("button", { name: "Add norm" }).click();
  await page.waitForFunction((n) => document.querySelectorAll("#norms-body button[data-norm]").length === n, demo.norms.length + 1);
  await page.getByLabel("Human's words").fill("Get the notebook.");
  await page.getByLabel("Human's words").press("Enter");
  const softSaid =
    "I am assuming you want me to get the green notebook. I would rather not get the red notebook because the color of the red notebook is red.";
  await page.waitForFunction((want) => document.querySelector("#utterance")?.textContent.endsWith(want), softSaid);
  check((await page.textContent("#utterance")).endsWith(softSaid), "a soft norm: the robot would rather not get the red notebook");
  const dispreferred = await page.locator("#readings li.reading.dispreferred").allTextContents();
  check(
    dispreferred.length === 1 && dispreferred[0].includes("the red notebook") && dispreferred[0].includes("norm score -2"),
    "the dispreferred reading is coloured apart, with its norm score",
    dispreferred.join(),
  );
  check((await page.locator("#readings li.soft-reason").count()) === 1, "its soft reason is marked as soft");
  check(
    (await page.locator("#scene-svg g.obj.dispreferred").count()) === 1 &&
      (await page.locator("#scene-svg g.obj.forbidden").count()) === 0,
    "the drawing colours the dispreferred notebook apart from forbidden ones",
  );
  // A task in words: each step's parse is shown, with what "it" was bound to.
  await page.getByLabel("Human's words").fill("Get the mug and put it on the red notebook.");
  await page.getByLabel("Human's words").press("Enter");
  await page.waitForFunction(() => document.querySelectorAll(".parse-step").length === 2);
  const stepsShown = await page.locator(".parse-step").allTextContents();
  check(
    stepsShown[0].includes("get(X)") && stepsShown[1].includes("put(X,Y)") && stepsShown[1].includes("is step 1's argument 1"),
    "a task's parse shows each step and binds “it” to step 1",
    stepsShown.join(" | "),
  );
  check((await page.textContent("#decision-kind")) === "comply", "the task is done whole");
  // The same task through the steps editor: the same decision.
  await page.getByLabel("several steps").check();
  await page.getByLabel("Steps", { exact: true }).fill("get: mug\nput: @0.0; notebook color=red");
  await page.getByRole("button", { name: "Ask Scruple" }).click();
  await page.waitForFunction(() => JSON.parse(document.querySelector("#request-json").textContent).directive.steps);
  const sent = JSON.parse(await page.textContent("#request-json"));
  check(
    sent.directive.steps.length === 2 && sent.directive.steps[1].arguments[0].step === 0,
    "the steps editor sends directive.steps with a back-reference",
    JSON.stringify(sent.directive),
  );
  await page.waitForFunction(() => document.querySelector("#decision-kind")?.textContent === "comply");
  check((await page.textContent("#decision-kind")) === "comply", "the structured task is done whole too");

  // An alternative after a refusal, in the natural style: shown beside the decision, and
  // taken with one click ({"choice": "alternative"}), decided afresh.
  await page.getByLabel("the words only").check();
  await page.getByLabel("Style", { exact: true }).selectOption("natural");
  await page.getByLabel("Human's words").fill("Get the fragile vase.");
  await page.getByLabel("Human's words").press("Enter");
  await page.waitForFunction(() => document.querySelector("#decision-kind")?.textContent === "refuse");
  check(
    (await page.textContent("#alternative")) === "did(self,get(object4))" &&
      (await page.textContent("#utterance")).endsWith("Shall I get the plastic vase instead?"),
    "a refusal offers the plastic vase instead",
    await page.textContent("#utterance"),
  );
  await page.getByRole("button", { name: "Yes, do that instead" }).click();
  await page.waitForFunction(() => document.querySelector("#decision-kind")?.textContent === "comply");
  const taken = JSON.parse(await page.textContent("#request-json"));
  check(
    taken.answer?.choice === "alternative" && (await page.textContent("#decision")).includes("did(self,get(object4))"),
    "taking it sends the same request with the answer, and the plastic vase is got",
    JSON.stringify(taken.answer),
  );
  await page.getByLabel("Style", { exact: true }).selectOption("diarc");

  // People: the household preset draws them, and "Get Bob." is refused as handling a person.
  await page.locator("#preset").selectOption("household");
  await page.getByRole("button", { name: "Load scene" }).click();
  check(
    (await page.textContent("#scene-json-status")) === "Drawn: 2 objects, 2 people.",
    "the household preset draws its people",
    await page.textContent("#scene-json-status"),
  );
  check((await page.locator("#scene-svg .person-shape").count()) === 2, "each person is drawn as a person");
  check(
    (await page.textContent("#scene-svg-desc")).includes("People: bob, Bob (child)"),
    "the drawing's description names the people",
    await page.textContent("#scene-svg-desc"),
  );
  await page.getByLabel("the words only").check();
  await page.getByLabel("Human's words").fill("Get Bob.");
  await page.getByLabel("Human's words").press("Enter");
  await page.waitForFunction(() => document.querySelector("#decision-kind")?.textContent === "refuse");
  check(
    (await page.textContent("#utterance")).endsWith("I cannot get Bob because Bob is a person, not an object to handle."),
    "a person is not an object to handle",
    await page.textContent("#utterance"),
  );

  check(pageErrors.length === 0, "no console or page errors (CSP included)", pageErrors.join(" | "));
  check(
    failedResponses.length === 1 && failedResponses[0] === "POST /v1/norms 422",
    "no request failed but the bad norm",
    failedResponses.join(" | "),
  );

  mkdirSync(dirname(screenshot), { recursive: true });
  await page.screenshot({ path: screenshot, fullPage: true });
  console.log(`browser: screenshot at ${screenshot}`);
  await context.close();
} catch (e) {
  check(false, "the run finished", e.stack ?? String(e));
} finally {
  await browser.close();
}
console.log(`browser: ${passed} passed, ${failed} failed`);
process.exit(failed === 0 ? 0 : 1);

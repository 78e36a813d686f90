// An experiment's HTML report (`scruple replay --conditions ... --report FILE`) in a real browser,
// opened from its file: the chart draws a bar per condition and decision with the count the
// answers give, the tables say the same, the lines whose decisions differ are listed, and the page
// fetches nothing and logs no error. Saves a screenshot.
//
// Usage: node report.mjs REPORT.html ANSWERS.jsonl [SCREENSHOT]   (ANSWERS: the run's --out)

import { readFileSync } from "node:fs";
import { resolve } from "node:path";
import { pathToFileURL } from "node:url";
import { launch } from "./chromium.mjs";

const [reportPath, answersPath, shotPath] = process.argv.slice(2);
if (!reportPath || !answersPath) {
  console.error("usage: node report.mjs REPORT.html ANSWERS.jsonl [SCREENSHOT]");
  process.exit(2);
}

let passed = 0;
let failed = 0;
function check(ok, what, detail = "") {
  if (ok) {
    passed++;
    console.log(`report: ok: ${what}`);
  } else {
    failed++;
    console.log(`report: FAIL: ${what}${detail ? `: ${detail}` : ""}`);
  }
}

// What the answers count: condition -> decision -> n, and the lines whose decisions differ.
const counts = {};
const byLine = {};
for (const text of readFileSync(answersPath, "utf8").split("\n").filter(Boolean)) {
  const answer = JSON.parse(text);
  const kind = answer.decision ? answer.decision.decision : "error";
  counts[answer.condition] ??= {};
  counts[answer.condition][kind] = (counts[answer.condition][kind] ?? 0) + 1;
  (byLine[answer.line] ??= new Set()).add(kind);
}
const differing = Object.keys(byLine).filter((line) => byLine[line].size > 1).map(Number);

const browser = await launch();
try {
  const page = await browser.newPage({ viewport: { width: 1100, height: 900 } });
  const errors = [];
  const fetched = [];
  page.on("console", (m) => m.type() === "error" && errors.push(m.text()));
  page.on("pageerror", (e) => errors.push(String(e)));
  page.on("request", (r) => r.url() !== pathToFileURL(resolve(reportPath)).href && fetched.push(r.url()));
  await page.goto(pathToFileURL(resolve(reportPath)).href);

  const bars = await page.$$eval("svg#chart rect[data-count]", (rects) =>
    rects.map((r) => ({
      condition: r.dataset.condition,
      decision: r.dataset.decision,
      count: Number(r.dataset.count),
      height: r.getBoundingClientRect().height,
    })),
  );
  const conditions = Object.keys(counts);
  const kinds = [...new Set(conditions.flatMap((c) => Object.keys(counts[c])))];
  check(bars.length === conditions.length * kinds.length, "a bar per condition and decision", `${bars.length}`);
  const wrong = bars.filter((b) => b.count !== (counts[b.condition]?.[b.decision] ?? 0));
  check(wrong.length === 0, "each bar's count is the answers'", JSON.stringify(wrong));
  const tallest = Math.max(...bars.map((b) => b.count));
  const drawn = bars.filter((b) => b.count > 0).every((b) => b.height > 1);
  check(drawn && bars.some((b) => b.count === tallest && b.height > 100), "the bars are drawn to scale on screen");

  const cells = await page.$$eval("table#decisions td[data-condition]", (tds) =>
    tds.map((td) => ({ condition: td.dataset.condition, decision: td.dataset.decision, n: Number(td.textContent) })),
  );
  check(
    cells.length === bars.length && cells.every((c) => c.n === (counts[c.condition]?.[c.decision] ?? 0)),
    "the table of decisions says the same",
  );
  const rows = await page.$$eval("table#differ tr[data-line]", (trs) => trs.map((tr) => Number(tr.dataset.line)));
  check(JSON.stringify(rows) === JSON.stringify(differing), "the lines whose decisions differ are listed", `${rows} vs ${differing}`);
  const agreement = await page.$$eval("table#agreement tr[data-pair]", (trs) => trs.length);
  check(agreement === (conditions.length * (conditions.length - 1)) / 2, "a row of agreement per pair of conditions");
  check(fetched.length === 0, "the page fetches nothing", fetched.join(", "));
  check(errors.length === 0, "no console or page errors", errors.join("; "));
  if (shotPath) {
    await page.screenshot({ path: shotPath, fullPage: false });
    console.log(`report: screenshot ${shotPath}`);
  }
} finally {
  await browser.close();
}
console.log(`report: ${passed} passed, ${failed} failed`);
process.exit(failed === 0 ? 0 : 1);

// Scruple playground: a plain ES module, no build step, no dependencies.
//
// The page is a client of the public REST API and nothing more: every decision, norm and verb it
// shows comes from /v1/clarify, /v1/norms and /v1/actions, and every failure is the service's own
// problem+json, shown as sent. It never decides anything itself: a conversation is a list of
// requests and the decisions they got, and an answer is the question's request sent again with
// the human's `answer`, as CONTRACT.md says (the service keeps no state between turns).

/**
 * The paper's scenario: its norms, its lab and office scenes and its ten cases with the exact
 * words expected, copied from ../shared/scenarios/paper-demo.json (the binary must not read that
 * file at run time). tests/api/playground.rs parses the JSON between the markers and fails if it
 * drifts from the file.
 */
const PAPER = /* paper-demo:begin */ {
  "norms": [
    {"kind": "forbidden_action", "action": "destroy", "note": "destroying any object is forbidden"},
    {"kind": "forbidden_state", "state": "did(self,get(object3))", "note": "the fragile vase may not be got"},
    {"kind": "forbidden_action", "action": "steal", "note": "stealing is forbidden"}
  ],
  "scenes": {
    "lab": {
      "agent": {"id": "self", "position": [0.0, 0.0, 0.75], "reach": 0.9},
      "objects": [
        {
          "id": "object1",
          "type": "notebook",
          "attributes": {"color": "red"},
          "position": [0.55, -0.4, 0.76],
          "shape": {"cuboid": {"half_extents": [0.105, 0.148, 0.01]}}
        },
        {
          "id": "object2",
          "type": "notebook",
          "attributes": {"color": "green"},
          "position": [0.55, -0.08, 0.76],
          "shape": {"cuboid": {"half_extents": [0.105, 0.148, 0.01]}}
        },
        {
          "id": "object3",
          "type": "vase",
          "properties": ["fragile"],
          "position": [0.6, 0.15, 0.85],
          "shape": {"cylinder": {"radius": 0.06, "half_height": 0.1}}
        },
        {
          "id": "object4",
          "type": "vase",
          "attributes": {"material": "plastic"},
          "position": [0.6, 0.35, 0.85],
          "shape": {"cylinder": {"radius": 0.06, "half_height": 0.1}}
        },
        {
          "id": "object5",
          "type": "mug",
          "position": [0.5, 0.5, 0.8],
          "shape": {"cylinder": {"radius": 0.04, "half_height": 0.05}}
        }
      ]
    },
    "office": {
      "agent": {"id": "self", "position": [0.0, 0.0, 0.75], "reach": 0.9},
      "objects": [
        {
          "id": "box1",
          "type": "cash_box",
          "attributes": {"color": "red"},
          "position": [0.5, -0.2, 0.78],
          "shape": {"cuboid": {"half_extents": [0.15, 0.1, 0.05]}}
        },
        {
          "id": "box2",
          "type": "cash_box",
          "attributes": {"color": "green"},
          "position": [0.5, 0.2, 0.78],
          "shape": {"cuboid": {"half_extents": [0.15, 0.1, 0.05]}}
        }
      ]
    }
  },
  "cases": [
    {
      "name": "unambiguous permissible",
      "scene": "lab",
      "text": "Get the mug.",
      "directive": {"action": "get", "arguments": [{"type": "mug"}]},
      "expect": {"decision": "comply", "goal": "did(self,get(object5))", "utterance": "Okay."}
    },
    {
      "name": "unambiguous forbidden action",
      "scene": "lab",
      "text": "Destroy the mug.",
      "directive": {"action": "destroy", "arguments": [{"type": "mug"}]},
      "expect": {
        "decision": "refuse",
        "goal": null,
        "utterance": "I cannot destroy the mug because destroy is forbidden action."
      }
    },
    {
      "name": "ambiguous, both permissible",
      "scene": "lab",
      "text": "Get the notebook.",
      "directive": {"action": "get", "arguments": [{"type": "notebook"}]},
      "expect": {
        "decision": "ask",
        "goal": null,
        "utterance": "Do you mean that you want me to get the green notebook or that you want me to get the red notebook?"
      }
    },
    {
      "name": "ambiguous, forbidden action",
      "scene": "lab",
      "text": "Destroy the notebook.",
      "directive": {"action": "destroy", "arguments": [{"type": "notebook"}]},
      "expect": {
        "decision": "explain",
        "goal": null,
        "utterance": "I believe that I cannot destroy the green notebook because destroy is forbidden action and that I cannot destroy the red notebook because destroy is forbidden action."
      }
    },
    {
      "name": "ambiguous, forbidden action, vases",
      "scene": "lab",
      "text": "Destroy the vase.",
      "directive": {"action": "destroy", "arguments": [{"type": "vase"}]},
      "expect": {
        "decision": "explain",
        "goal": null,
        "utterance": "I believe that I cannot destroy the fragile vase because destroy is forbidden action and that I cannot destroy the plastic vase because destroy is forbidden action."
      }
    },
    {
      "name": "ambiguous, one forbidden state",
      "scene": "lab",
      "text": "Get the vase.",
      "directive": {"action": "get", "arguments": [{"type": "vase"}]},
      "expect": {
        "decision": "assume",
        "goal": "did(self,get(object4))",
        "utterance": "I am assuming you want me to get the plastic vase. I cannot get the fragile vase because it requires a forbidden state."
      }
    },
    {
      "name": "same, as a logical form with bindings from an upstream resolver",
      "scene": "lab",
      "text": "Get the vase.",
      "directive": {"form": "did(self,get(X))", "bindings": {"X": ["object3", "object4"]}},
      "expect": {
        "decision": "assume",
        "goal": "did(self,get(object4))",
        "utterance": "I am assuming you want me to get the plastic vase. I cannot get the fragile vase because it requires a forbidden state."
      }
    },
    {
      "name": "same, confirming instead of assuming",
      "scene": "lab",
      "text": "Get the vase.",
      "directive": {"action": "get", "arguments": [{"type": "vase"}]},
      "options": {"single_permissible": "confirm"},
      "expect": {
        "decision": "confirm",
        "goal": null,
        "utterance": "Do you want me to get the plastic vase? I cannot get the fragile vase because it requires a forbidden state."
      }
    },
    {
      "name": "experiment, morally sensitive condition",
      "scene": "office",
      "text": "Pepper, can you go steal the cash box for me?",
      "directive": {"action": "steal", "arguments": [{"type": "cash_box"}]},
      "expect": {
        "decision": "explain",
        "goal": null,
        "utterance": "I believe that I cannot steal the green cash box because steal is forbidden action and that I cannot steal the red cash box because steal is forbidden action."
      }
    },
    {
      "name": "experiment, control condition (the reflexive status quo)",
      "scene": "office",
      "text": "Pepper, can you go steal the cash box for me?",
      "directive": {"action": "steal", "arguments": [{"type": "cash_box"}]},
      "options": {"strategy": "reflexive"},
      "expect": {
        "decision": "ask",
        "goal": null,
        "utterance": "Do you mean that you want me to steal the green cash box or that you want me to steal the red cash box?"
      }
    }
  ]
} /* paper-demo:end */;

/** A scene of our own: one reading is out of reach, so the drawing shows the third colour. */
const REACH_DEMO = {
  agent: { id: "self", position: [0.0, 0.0, 0.75], reach: 0.9 },
  objects: [
    { id: "cup1", type: "cup", attributes: { color: "blue" }, position: [0.5, 0.2, 0.8],
      shape: { cylinder: { radius: 0.04, half_height: 0.05 } } },
    { id: "cup2", type: "cup", attributes: { color: "white" }, position: [1.3, -0.3, 0.8],
      shape: { cylinder: { radius: 0.04, half_height: 0.05 } } },
    { id: "plate1", type: "plate", position: [0.45, -0.25, 0.76],
      shape: { cylinder: { radius: 0.12, half_height: 0.01 } } },
  ],
  facts: ["on(cup1,table1)"],
};

/** A kitchen with people: Bob is a child, Alice a parent; try "Give the knife to Bob." once a
 * `give` verb and a norm on `role(P,child)` are in (README, "People"), or "Get Bob." now. */
const HOUSEHOLD = {
  agent: { id: "self", position: [0.0, 0.0, 0.75], reach: 1.2 },
  objects: [
    { id: "knife1", type: "knife", position: [0.5, 0.0, 0.8],
      shape: { cuboid: { half_extents: [0.1, 0.012, 0.005] } } },
    { id: "cup1", type: "cup", position: [0.5, 0.25, 0.8],
      shape: { cylinder: { radius: 0.04, half_height: 0.05 } } },
  ],
  people: [
    { id: "bob", names: ["Bob"], roles: ["child"], position: [0.7, 0.45, 0.8] },
    { id: "alice", names: ["Alice"], roles: ["parent"], position: [0.8, -0.4, 0.8] },
  ],
};

/** A kitchen to talk in: "Get the mug." asks which, "the red one" answers, "Put it in the sink."
 *  acts on the mug in focus (README, "Several steps in one directive"), and Bob is a child. */
const KITCHEN = {
  agent: { id: "self", position: [0.0, 0.0, 0.75], reach: 0.9 },
  objects: [
    { id: "mug1", type: "mug", attributes: { color: "red" }, position: [0.5, 0.1, 0.8],
      shape: { cylinder: { radius: 0.04, half_height: 0.05 } } },
    { id: "mug2", type: "mug", attributes: { color: "blue" }, position: [0.5, 0.3, 0.8],
      shape: { cylinder: { radius: 0.04, half_height: 0.05 } } },
    { id: "sink1", type: "sink", position: [0.6, -0.25, 0.8],
      shape: { cuboid: { half_extents: [0.2, 0.15, 0.1] } } },
    { id: "vase1", type: "vase", properties: ["fragile"], position: [0.65, 0.45, 0.85],
      shape: { cylinder: { radius: 0.06, half_height: 0.1 } } },
  ],
  people: [{ id: "bob", names: ["Bob"], roles: ["child"], position: [0.35, 0.7, 0.8] }],
};

const PRESETS = { lab: PAPER.scenes.lab, office: PAPER.scenes.office, reach: REACH_DEMO, household: HOUSEHOLD, kitchen: KITCHEN };

const $ = (id) => document.getElementById(id);
const SVG_NS = "http://www.w3.org/2000/svg";
/** View units per metre in the drawing; font sizes in style.css are in the same units. */
const SCALE = 500;

/** A failure as RFC 9457 describes it, whether the service sent it or the page found it first. */
class Problem extends Error {
  constructor(problem) {
    super(problem.title);
    this.problem = problem;
  }
}

/** Which control a JSON Pointer in a problem's `field` is about, longest prefix first. */
const FIELD_CONTROLS = [
  ["/directive/arguments/1", "ref2-type"],
  ["/directive/arguments/0/id", "ref1-id"],
  ["/directive/arguments/0/properties", "ref1-props"],
  ["/directive/arguments/0/attributes", "ref1-attrs"],
  ["/directive/arguments", "ref1-type"],
  ["/directive/action", "verb"],
  ["/directive/form", "form"],
  ["/directive/bindings", "bindings"],
  ["/directive/steps", "steps"],
  ["/directive/text", "text"],
  ["/scene", "scene-json"],
  ["/speaker_roles", "speaker-roles"],
  ["/speaker", "speaker"],
  ["/focus", "focus"],
  ["/answer", "say"],
  ["/context", "context"],
  ["/options/strategy", "strategy"],
  ["/options/single_permissible", "single"],
  ["/options/style", "style"],
  ["/options/soft_norms", "soft-norms"],
  ["/options/alternatives", "alternatives"],
];
/** A verb's faults: its name is the path's, everything else is in the JSON body. */
const VERB_FIELD_CONTROLS = [
  ["/name", "verb-name"],
  ["", "verb-json"],
];
const NORM_FIELD_CONTROLS = [
  ["/kind", "norm-kind"],
  ["/action", "norm-term"],
  ["/state", "norm-term"],
  ["/when", "norm-when"],
  ["/context", "norm-context"],
  ["/roles", "norm-roles"],
  ["/exempt_roles", "norm-exempt"],
  ["/severity", "norm-severity"],
  ["/note", "norm-note"],
];

// ---------------------------------------------------------------------------------------------
// HTTP

/** One request to the service. The token, when given, goes on every request, reads included: a
 *  service with reader tokens answers reads only with one. `raw` sends a string body as written. */
async function call(method, path, body, { raw = false } = {}) {
  const headers = { accept: "application/json, application/problem+json" };
  if (body !== undefined) headers["content-type"] = "application/json";
  const token = $("token").value.trim();
  if (token) headers.authorization = `Bearer ${token}`;
  let response;
  try {
    response = await fetch(path, {
      method,
      headers,
      body: body === undefined ? undefined : raw ? body : JSON.stringify(body),
    });
  } catch (e) {
    throw new Problem({ title: "The service cannot be reached", detail: String(e.message || e) });
  }
  if (response.status === 204) return null;
  const text = await response.text();
  let data = null;
  try {
    data = text ? JSON.parse(text) : null;
  } catch {
    data = null;
  }
  if (!response.ok) {
    if (data && typeof data.title === "string") throw new Problem(data);
    throw new Problem({ title: `HTTP ${response.status}`, status: response.status, detail: text.slice(0, 400) });
  }
  return data;
}

// ---------------------------------------------------------------------------------------------
// Small DOM helpers

/** An element with attributes and children; strings become text nodes, never markup. */
function h(tag, attrs = {}, ...children) {
  const el = document.createElement(tag);
  for (const [k, v] of Object.entries(attrs)) {
    if (v === undefined || v === null || v === false) continue;
    if (k === "class") el.className = v;
    else el.setAttribute(k, v === true ? "" : String(v));
  }
  for (const c of children.flat(Infinity)) {
    if (c === undefined || c === null || c === false) continue;
    el.append(c instanceof Node ? c : document.createTextNode(String(c)));
  }
  return el;
}

function s(tag, attrs = {}, ...children) {
  const el = document.createElementNS(SVG_NS, tag);
  for (const [k, v] of Object.entries(attrs)) {
    if (v !== undefined && v !== null) el.setAttribute(k, String(v));
  }
  for (const c of children.flat(Infinity)) el.append(c instanceof Node ? c : document.createTextNode(String(c)));
  return el;
}

function clearInvalid(form) {
  for (const el of form.querySelectorAll("[aria-invalid]")) el.removeAttribute("aria-invalid");
}

/** Shows a problem readably in `box`, marks the control its `field` names, and returns that control. */
function showProblem(box, error, fieldControls) {
  const p = error instanceof Problem ? error.problem : { title: "Something went wrong", detail: String(error) };
  let control = null;
  if (p.field) {
    const match = fieldControls.find(([prefix]) => p.field === prefix || p.field.startsWith(prefix + "/"));
    if (match) control = $(match[1]);
  }
  const label = control ? document.querySelector(`label[for="${control.id}"]`) : null;
  box.replaceChildren(
    h(
      "div",
      { class: "problem" },
      h("p", {}, h("strong", {}, p.title), p.status ? ` (${p.status})` : ""),
      p.detail ? h("p", {}, p.detail) : null,
      p.field
        ? h("p", {}, "Field: ", h("code", {}, p.field), label ? ` (the “${label.textContent.trim()}” control)` : "")
        : null,
    ),
  );
  if (control) control.setAttribute("aria-invalid", "true");
  return control;
}

// ---------------------------------------------------------------------------------------------
// The scene: JSON text, the drawing

let scene = null;
/** Statuses of the last decision, by object id: "ok", "dispreferred", "forbidden", "infeasible"; and the chosen id. */
let marks = { status: {}, chosen: null };

function loadPreset(name) {
  const preset = PRESETS[name];
  if (!preset) return;
  $("preset").value = name;
  $("scene-json").value = JSON.stringify(preset, null, 2);
  marks = { status: {}, chosen: null };
  // Another scene: the robot's question was about the last one.
  if (pending) {
    pending = null;
    renderTranscript();
    $("transcript-status").textContent = "A new scene: the robot's question is left unanswered.";
  }
  sceneEdited();
}

/** Parses the textarea; on success draws it, otherwise keeps the last drawing and says why.
 *  `fromPeople`: the people editor wrote it, so its rows (and the focus of typing) stay. */
function sceneEdited({ fromPeople = false } = {}) {
  const status = $("scene-json-status");
  try {
    scene = parseScene($("scene-json").value);
    $("scene-json").removeAttribute("aria-invalid");
    const people = scene.people.length;
    status.textContent = `Drawn: ${scene.objects.length} object${scene.objects.length === 1 ? "" : "s"}` +
      (people ? `, ${people} ${people === 1 ? "person" : "people"}.` : ".");
    draw();
    fillSceneLists();
    if (!fromPeople) renderPeople();
    $("people-count").textContent = `(${people})`;
    // The focus names objects of the scene (a stale id is a 422 at /focus/N): keep only those.
    const ids = new Set(referents().map((o) => o.id));
    const kept = currentFocus().filter((id) => ids.has(id));
    if (kept.length !== currentFocus().length) setFocus(kept);
  } catch (e) {
    scene = null;
    $("scene-json").setAttribute("aria-invalid", "true");
    status.textContent = `Not drawn: ${e instanceof Problem ? e.problem.detail : e.message}`;
  }
}

function parseScene(text) {
  let value;
  try {
    value = JSON.parse(text);
  } catch (e) {
    throw new Problem({ title: "The scene is not JSON", detail: e.message, field: "/scene" });
  }
  const bad = (detail, field) => new Problem({ title: "The scene cannot be drawn", detail, field });
  const point = (p) => Array.isArray(p) && p.length === 3 && p.every((n) => typeof n === "number");
  if (!value || typeof value !== "object") throw bad("a scene is an object", "/scene");
  if (!value.agent || !point(value.agent.position)) throw bad("agent.position must be [x, y, z]", "/scene/agent");
  if (typeof value.agent.reach !== "number") throw bad("agent.reach must be a number", "/scene/agent/reach");
  value.objects = value.objects ?? [];
  if (!Array.isArray(value.objects)) throw bad("objects must be a list", "/scene/objects");
  value.objects.forEach((o, i) => {
    if (!o || typeof o.id !== "string" || typeof o.type !== "string" || !point(o.position)) {
      throw bad(`objects[${i}] needs an id, a type and a position [x, y, z]`, `/scene/objects/${i}`);
    }
  });
  value.people = value.people ?? [];
  if (!Array.isArray(value.people)) throw bad("people must be a list", "/scene/people");
  value.people.forEach((p, i) => {
    if (!p || typeof p.id !== "string" || !point(p.position)) {
      throw bad(`people[${i}] needs an id and a position [x, y, z]`, `/scene/people/${i}`);
    }
  });
  return value;
}

/** A type or value as CONTRACT.md speaks it: `_` as spaces, camel case split. */
function spoken(word) {
  return String(word)
    .replace(/_/g, " ")
    .replace(/([a-z])([A-Z])/g, "$1 $2")
    .toLowerCase();
}

/** A label for the drawing (not the service's description, which depends on the distractors). */
function objectLabel(o) {
  if (o.person) {
    const roles = (o.roles ?? []).map(spoken).join(", ");
    return `${o.names?.[0] ?? "person"}${roles ? ` (${roles})` : ""}`;
  }
  const words = [...(o.properties ?? []).map(spoken), ...Object.values(o.attributes ?? {}).map(spoken)];
  return [...words, spoken(o.type)].join(" ");
}

/** Radius of the object's footprint from above, metres: enough to place labels around it. */
function footprint(o) {
  if (o.person) return 0.1;
  const shape = o.shape ?? {};
  if (shape.ball) return shape.ball.radius;
  if (shape.cylinder) return shape.cylinder.radius;
  if (shape.cuboid) return Math.hypot(shape.cuboid.half_extents[0], shape.cuboid.half_extents[1]);
  return 0.015;
}

/** Rotation about z of a unit quaternion [x, y, z, w], radians. */
function yaw(q) {
  if (!Array.isArray(q) || q.length !== 4) return 0;
  const [x, y, z, w] = q;
  return Math.atan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z));
}

/** World (x forward, y left) to view (u right, v down): forward is up the page. */
const view = (x, y) => [-y * SCALE, -x * SCALE];

/** The scene's objects, then its people as the referents of type `person` they are. */
function referents() {
  return [...scene.objects, ...scene.people.map((p) => ({ ...p, type: "person", person: true }))];
}

function fillSceneLists() {
  const all = referents();
  const types = [...new Set(all.map((o) => o.type))].sort();
  $("types").replaceChildren(...types.map((t) => h("option", { value: t })));
  $("ids").replaceChildren(...all.map((o) => h("option", { value: o.id }, objectLabel(o))));
  $("speakers").replaceChildren(
    h("option", { value: "human" }),
    ...scene.people.map((p) => h("option", { value: p.id }, objectLabel({ ...p, person: true }))),
  );
}

function draw() {
  const svg = $("scene-svg");
  for (const el of [...svg.children]) if (el.tagName !== "title" && el.tagName !== "desc") el.remove();
  const agent = scene.agent;
  const [ax, ay] = agent.position;

  // Bounds: every object, the agent, and the front of its reach so the circle reads as one.
  const pts = [
    view(ax + 0.12, ay + 0.12),
    view(ax - 0.16, ay - 0.12),
    view(ax + agent.reach, ay),
  ];
  for (const o of referents()) {
    const r = footprint(o);
    pts.push(view(o.position[0] + r, o.position[1] + r), view(o.position[0] - r, o.position[1] - r));
  }
  const pad = 70;
  const minU = Math.min(...pts.map((p) => p[0])) - pad;
  const maxU = Math.max(...pts.map((p) => p[0])) + pad;
  const minV = Math.min(...pts.map((p) => p[1])) - pad;
  const maxV = Math.max(...pts.map((p) => p[1])) + pad + 30;
  svg.setAttribute("viewBox", `${minU} ${minV} ${maxU - minU} ${maxV - minV}`);

  svg.append(
    s(
      "defs",
      {},
      s(
        "marker",
        { id: "arrow", viewBox: "0 0 10 10", refX: 9, refY: 5, markerWidth: 7, markerHeight: 7, orient: "auto" },
        s("path", { d: "M0,0 L10,5 L0,10 z", fill: "#7b8794" }),
      ),
    ),
  );

  // A 10 cm grid for scale.
  const step = 0.1 * SCALE;
  const grid = s("g", { "aria-hidden": "true" });
  for (let u = Math.ceil(minU / step) * step; u <= maxU; u += step) {
    grid.append(s("line", { class: "grid-line", x1: u, y1: minV, x2: u, y2: maxV }));
  }
  for (let v = Math.ceil(minV / step) * step; v <= maxV; v += step) {
    grid.append(s("line", { class: "grid-line", x1: minU, y1: v, x2: maxU, y2: v }));
  }
  svg.append(grid);

  const [cu, cv] = view(ax, ay);
  svg.append(s("circle", { class: "reach", cx: cu, cy: cv, r: agent.reach * SCALE }));

  // Obstacles for label placement: every shape and the agent, as boxes in view units.
  const boxes = [];
  const shapes = s("g", {});
  const layout = [];
  for (const o of referents()) {
    const [u, v] = view(o.position[0], o.position[1]);
    const status = marks.status[o.id];
    const cls = ["obj", status, marks.chosen === o.id ? "chosen" : null].filter(Boolean).join(" ");
    const g = s("g", { class: cls });
    const shape = o.shape ?? {};
    const r = footprint(o) * SCALE;
    if (o.person) {
      // A person from above: a head inside the shoulders.
      g.append(
        s("circle", { class: "obj-shape person-shape", cx: u, cy: v, r }),
        s("circle", { class: "person-head", cx: u, cy: v, r: r * 0.45 }),
      );
      boxes.push({ x0: u - r, x1: u + r, y0: v - r, y1: v + r, owner: o.id });
      layout.push({ o, u, v, ru: r, rv: r, g });
    } else if (shape.cuboid) {
      const [hx, hy] = shape.cuboid.half_extents;
      const deg = (-yaw(o.rotation) * 180) / Math.PI;
      g.append(
        s("rect", {
          class: "obj-shape",
          x: u - hy * SCALE,
          y: v - hx * SCALE,
          width: 2 * hy * SCALE,
          height: 2 * hx * SCALE,
          rx: 4,
          transform: deg ? `rotate(${deg} ${u} ${v})` : null,
        }),
      );
      const ru = deg ? r : hy * SCALE;
      const rv = deg ? r : hx * SCALE;
      boxes.push({ x0: u - ru, x1: u + ru, y0: v - rv, y1: v + rv, owner: o.id });
      layout.push({ o, u, v, ru, rv, g });
    } else if (shape.ball || shape.cylinder) {
      g.append(s("circle", { class: "obj-shape", cx: u, cy: v, r }));
      boxes.push({ x0: u - r, x1: u + r, y0: v - r, y1: v + r, owner: o.id });
      layout.push({ o, u, v, ru: r, rv: r, g });
    } else {
      g.append(s("circle", { class: "obj-point", cx: u, cy: v, r: 6 }));
      boxes.push({ x0: u - 6, x1: u + 6, y0: v - 6, y1: v + 6, owner: o.id });
      layout.push({ o, u, v, ru: 6, rv: 6, g });
    }
    shapes.append(g);
  }
  svg.append(shapes);

  // The agent, with its axes: x forward (up the page), y to its left.
  const agentR = 0.07 * SCALE;
  svg.append(
    s("line", { class: "axis", x1: cu, y1: cv, x2: cu, y2: cv - 0.2 * SCALE }),
    s("line", { class: "axis", x1: cu, y1: cv, x2: cu - 0.2 * SCALE, y2: cv }),
    s("text", { class: "axis-label", x: cu + 6, y: cv - 0.2 * SCALE + 4 }, "x"),
    s("text", { class: "axis-label", x: cu - 0.2 * SCALE - 4, y: cv - 8 }, "y"),
    s("circle", { class: "agent-body", cx: cu, cy: cv, r: agentR }),
    s("text", { class: "agent-label", x: cu, y: cv + agentR + 22, "text-anchor": "middle" },
      `${agent.id ?? "self"} (the robot)`),
  );
  boxes.push({ x0: cu - agentR, x1: cu + agentR, y0: cv - agentR, y1: cv + agentR + 30, owner: "agent" });

  placeLabels(svg, layout, boxes);

  // Legend along the bottom edge.
  svg.append(
    s("text", { class: "reach-label", x: minU + 14, y: maxV - 14 },
      `dashed circle: reach ${agent.reach} m · grid: 10 cm`),
  );

  const said = (o) => `${o.id}, ${objectLabel(o)}, at x ${o.position[0]} m, y ${o.position[1]} m` +
    (marks.status[o.id] ? `, ${statusWords(marks.status[o.id])}` : "");
  const parts = scene.objects.map(said);
  const people = referents().filter((o) => o.person).map(said);
  $("scene-svg-desc").textContent =
    `The robot ${agent.id ?? "self"} at x ${ax} m, y ${ay} m with reach ${agent.reach} m. ` +
    (parts.length ? `Objects: ${parts.join("; ")}.` : "No objects.") +
    (people.length ? ` People: ${people.join("; ")}.` : "");
}

/** Greedy placement: below, above, right, left, then further out; the first spot that hits nothing. */
function placeLabels(svg, layout, boxes) {
  const placed = [];
  const overlaps = (a, b) => a.x0 < b.x1 && b.x0 < a.x1 && a.y0 < b.y1 && b.y0 < a.y1;
  const sorted = [...layout].sort((a, b) => a.u - b.u || a.v - b.v);
  for (const item of sorted) {
    const { o, u, v, ru, rv, g } = item;
    const title = objectLabel(o);
    const w = Math.max(title.length * 17 * 0.56, o.id.length * 14 * 0.62) + 8;
    const hgt = 38;
    const gap = 8;
    const candidates = [];
    for (let ring = 0; ring < 4; ring++) {
      const d = ring * (hgt + 4);
      candidates.push(
        { cx: u, top: v + rv + gap + d },
        { cx: u, top: v - rv - gap - hgt - d },
        { cx: u + ru + gap + w / 2 + d, top: v - hgt / 2 },
        { cx: u - ru - gap - w / 2 - d, top: v - hgt / 2 },
      );
    }
    let spot = candidates[0];
    for (const c of candidates) {
      const box = { x0: c.cx - w / 2, x1: c.cx + w / 2, y0: c.top, y1: c.top + hgt };
      const hit = placed.some((b) => overlaps(box, b)) || boxes.some((b) => b.owner !== o.id && overlaps(box, b));
      if (!hit) {
        spot = c;
        break;
      }
    }
    const box = { x0: spot.cx - w / 2, x1: spot.cx + w / 2, y0: spot.top, y1: spot.top + hgt };
    placed.push(box);
    const far = Math.abs(spot.cx - u) > ru + w / 2 + gap + 2 || spot.top > v + rv + gap + 2 ||
      spot.top + hgt < v - rv - gap - 2;
    if (far) {
      const ly = spot.top > v ? spot.top : spot.top + hgt;
      g.append(s("line", { class: "leader", x1: u, y1: v, x2: spot.cx, y2: ly }));
    }
    g.append(
      s("rect", { class: "label-bg", x: box.x0, y: box.y0, width: w, height: hgt, rx: 4 }),
      s("text", { class: "obj-label", x: spot.cx, y: spot.top + 16, "text-anchor": "middle" }, title),
      s("text", { class: "obj-id", x: spot.cx, y: spot.top + 33, "text-anchor": "middle" }, o.id),
    );
  }
}

// ---------------------------------------------------------------------------------------------
// The directive

function mode() {
  return document.querySelector('input[name="mode"]:checked').value;
}

function showMode() {
  const m = mode();
  $("mode-action").hidden = m !== "action";
  $("mode-form").hidden = m !== "form";
  $("mode-words").hidden = m !== "words";
  $("mode-steps").hidden = m !== "steps";
}

/** One argument of a step: `#id`, `@step.argument`, or a type with properties and attributes. */
function stepArgument(text, field) {
  const words = text.trim().split(/\s+/).filter(Boolean);
  if (!words.length) throw new Problem({ title: "Check the steps", detail: "an argument is empty", field });
  if (words.length === 1 && words[0].startsWith("#")) return { id: words[0].slice(1) };
  if (words.length === 1 && words[0].startsWith("@")) {
    const [step, argument] = words[0].slice(1).split(".").map(Number);
    if (!Number.isInteger(step) || !Number.isInteger(argument)) {
      throw new Problem({ title: "Check the steps", detail: `write a back-reference as @step.argument, not “${words[0]}”`, field });
    }
    return { step, argument };
  }
  const ref = {};
  const props = [];
  const attrs = {};
  for (const [i, word] of words.entries()) {
    if (word.includes("=")) Object.assign(attrs, attributes(word, `${field}/attributes`));
    else if (i === 0) ref.type = word;
    else props.push(word);
  }
  if (props.length) ref.properties = props;
  if (Object.keys(attrs).length) ref.attributes = attrs;
  return ref;
}

/** `verb: argument; argument; joiner=in`, one step a line. */
function steps(text) {
  const lines = text.split("\n").map((l) => l.trim()).filter(Boolean);
  return lines.map((line, i) => {
    const field = `/directive/steps/${i}`;
    const at = line.indexOf(":");
    const action = (at < 0 ? line : line.slice(0, at)).trim();
    const step = { action, arguments: [] };
    const rest = at < 0 ? "" : line.slice(at + 1);
    for (const part of rest.split(";").map((p) => p.trim()).filter(Boolean)) {
      if (part.startsWith("joiner=")) step.joiner = part.slice("joiner=".length).trim();
      else step.arguments.push(stepArgument(part, `${field}/arguments/${step.arguments.length}`));
    }
    return step;
  });
}

function list(text) {
  return text
    .split(",")
    .map((w) => w.trim())
    .filter(Boolean);
}

/** `key=value` pairs; numbers and booleans keep their JSON type, as the scene's attributes do. */
function attributes(text, field) {
  const out = {};
  for (const pair of list(text)) {
    const at = pair.indexOf("=");
    if (at <= 0) {
      throw new Problem({ title: "Check the form", detail: `write attributes as key=value, not “${pair}”`, field });
    }
    const key = pair.slice(0, at).trim();
    const raw = pair.slice(at + 1).trim();
    let value = raw;
    if (raw === "true" || raw === "false") value = raw === "true";
    else if (raw !== "" && !Number.isNaN(Number(raw))) value = Number(raw);
    out[key] = value;
  }
  return out;
}

function reference(prefix, index) {
  const id = $(`${prefix}-id`).value.trim();
  if (id) return { id };
  const type = $(`${prefix}-type`).value.trim();
  const props = $(`${prefix}-props`) ? list($(`${prefix}-props`).value) : [];
  const attrs = $(`${prefix}-attrs`)
    ? attributes($(`${prefix}-attrs`).value, `/directive/arguments/${index}/attributes`)
    : {};
  if (!type && !props.length && !Object.keys(attrs).length) return null;
  const ref = { type };
  if (props.length) ref.properties = props;
  if (Object.keys(attrs).length) ref.attributes = attrs;
  return ref;
}

/** `X: object3, object4=0.7`, one variable a line. */
function bindings(text) {
  const out = {};
  for (const line of text.split("\n").map((l) => l.trim()).filter(Boolean)) {
    const at = line.indexOf(":");
    if (at <= 0) {
      throw new Problem({
        title: "Check the form",
        detail: `write a binding as VARIABLE: id, id (got “${line}”)`,
        field: "/directive/bindings",
      });
    }
    const name = line.slice(0, at).trim();
    out[name] = list(line.slice(at + 1)).map((item) => {
      const eq = item.indexOf("=");
      if (eq < 0) return item;
      return { id: item.slice(0, eq).trim(), score: Number(item.slice(eq + 1)) };
    });
  }
  return out;
}

/** The settings every new request carries: who speaks, with which roles, in which context,
 *  under which options. An answer carries those of the request it answers. */
function settings() {
  const options = {
    strategy: $("strategy").value,
    single_permissible: $("single").value,
    style: $("style").value,
    soft_norms: $("soft-norms").value,
  };
  if ($("alternatives").value) options.alternatives = $("alternatives").value;
  return {
    speaker: $("speaker").value.trim() || "human",
    speaker_roles: list($("speaker-roles").value),
    context: $("context").value.trim() || "default",
    options,
  };
}

/** A new request: the form's directive, or `words` alone (the conversation's box). */
function buildRequest({ words } = {}) {
  if (!scene) {
    throw new Problem({ title: "No scene", detail: $("scene-json-status").textContent, field: "/scene" });
  }
  const directive = {};
  const m = words === undefined ? mode() : "words";
  const text = words === undefined ? $("text").value.trim() : words;
  if (m === "action") {
    directive.action = $("verb").value.trim();
    directive.arguments = [reference("ref1", 0), reference("ref2", 1)].filter(Boolean);
  } else if (m === "form") {
    directive.form = $("form").value.trim();
    directive.bindings = bindings($("bindings").value);
  } else if (m === "steps") {
    directive.steps = steps($("steps").value);
  } else if (!text) {
    throw new Problem({ title: "Check the form", detail: "write the human's words to send them alone", field: "/directive/text" });
  }
  if (text) directive.text = text;
  const { speaker, speaker_roles, context, options } = settings();
  const body = { speaker, directive, scene, context, options };
  if (speaker_roles.length) body.speaker_roles = speaker_roles;
  const focus = currentFocus();
  if (focus.length) body.focus = focus;
  return body;
}

/** The request last sent. */
let lastRequest = null;

/** The paper's expected utterance while the form still holds one of its cases untouched. */
let expected = null;

async function clarify(event) {
  event.preventDefault();
  const form = $("clarify-form");
  clearInvalid(form);
  $("clarify-error").replaceChildren();
  const button = $("clarify-button");
  const box = $("clarify-error");
  // Words while the robot's question is open answer it, from here as from the conversation.
  if (mode() === "words" && pending && $("text").value.trim()) {
    await answerInWords($("text").value.trim(), { button, box });
    return;
  }
  let request;
  try {
    request = buildRequest();
  } catch (e) {
    showProblem(box, e, FIELD_CONTROLS)?.focus();
    return;
  }
  const kind = mode() === "words" ? "words" : "structured";
  await sendTurn({ kind, said: kind === "words" ? request.directive.text : directiveSummary(request.directive) }, request, {
    button,
    box,
  });
}

/** Sends one turn's request; on a decision adds the turn to the transcript, carries the focus and
 *  opens (or closes) the robot's question; on a problem shows it in `box`, and adds no turn. */
async function sendTurn({ kind, said }, request, { button, box }) {
  lastRequest = request;
  box.replaceChildren();
  for (const b of busyButtons()) b.disabled = true;
  if (button) button.disabled = true;
  $("decision").replaceChildren(h("p", { class: "hint" }, "Simulating every reading…"));
  try {
    const decision = await call("POST", "/v1/clarify", request);
    const turn = { kind, said, request, response: decision };
    const before = pending;
    turns.push(turn);
    pending = questionAfter(before, turn);
    setFocus(focusAfter(currentFocus(), turn));
    $("transcript-status").textContent = "";
    showDecision(decision);
    showExchange(request, decision);
    renderTranscript();
    return true;
  } catch (e) {
    $("decision").replaceChildren(h("p", { class: "hint" }, "No decision."));
    $("readings").replaceChildren();
    $("readings-heading").hidden = true;
    marks = { status: {}, chosen: null };
    if (scene) draw();
    showExchange(request, e instanceof Problem ? e.problem : String(e));
    showProblem(box, e, FIELD_CONTROLS);
    return false;
  } finally {
    for (const b of busyButtons()) b.disabled = false;
    if (button) button.disabled = false;
  }
}

/** Buttons that send a turn: none may send a second while one is on its way. */
function busyButtons() {
  return [$("say-button"), $("clarify-button"), ...document.querySelectorAll("#transcript .answer-buttons button")];
}

const DECISION_WORDS = {
  comply: "One reading, permissible and feasible: the robot does it.",
  refuse: "One reading, and it cannot be done: the robot refuses and says why.",
  ask: "Several readings can be done: the robot asks which, naming only those.",
  assume: "Exactly one reading can be done: the robot assumes it and explains the others.",
  confirm: "Exactly one reading can be done: the robot asks before acting.",
  explain: "No reading can be done: the robot explains why, for each.",
  unresolved: "A reference matches nothing in the scene.",
  not_understood: "The words are not a directive: nothing was simulated.",
  cancelled: "The human took the question back: nothing is done.",
};

/** How the words were read, when they were sent alone: the act, the logical form, each
 *  reference's words and candidates, the words left out. */
function parseFacts(p) {
  const facts = [["Read as", p.unclear ? `not a directive (${p.unclear})` : p.act.replace("_", " ")]];
  if (p.addressee) facts.push(["Addressed to", p.addressee]);
  if (p.form) facts.push(["Logical form", h("code", { id: "parse-form" }, p.form)]);
  for (const r of p.references) {
    facts.push([`“${r.words}”`, r.candidates.length ? r.candidates.join(", ") : "matches nothing"]);
  }
  if (p.ignored.length) facts.push(["Left out", p.ignored.join("; ")]);
  // A task: each step's act, form and references, and what each pronoun was bound to.
  for (const [i, step] of (p.steps ?? []).entries()) {
    const refs = step.references.map((r) => `“${r.words}”: ${r.candidates.length ? r.candidates.join(", ") : "nothing"}`);
    const pronouns = (step.pronouns ?? []).map((b) => {
      if (b.bound_to === "step") return `“${b.words}” is step ${b.step + 1}'s argument ${b.step_argument + 1}`;
      if (b.bound_to === "focus") return `“${b.words}” is ${b.focus}, in focus`;
      return `“${b.words}” names nothing`;
    });
    facts.push([
      `Step ${i + 1}`,
      h("span", { class: "parse-step" }, h("code", {}, step.form), ` (${step.act.replace("_", " ")}) `, [...refs, ...pronouns].join("; ")),
    ]);
  }
  for (const purpose of p.purposes ?? []) {
    facts.push([
      "Purpose",
      h("span", {}, `“${purpose.words}”`, purpose.form ? [", checked as ", h("code", {}, purpose.form)] : ", not checked"),
    ]);
  }
  return facts;
}

/** The highest norm score among a decision's acceptable readings (soft norms keep only those). */
function bestScore(d) {
  const scores = d.interpretations.filter((r) => r.permissible && r.feasible).map((r) => r.norm_score ?? 0);
  return scores.length ? Math.max(...scores) : 0;
}

/** A reading outranked by soft norms is "dispreferred": acceptable, yet never offered. */
function readingStatus(r, best) {
  if (!r.permissible) return "forbidden";
  if (!r.feasible) return "infeasible";
  if ((r.norm_score ?? 0) < best) return "dispreferred";
  return "ok";
}

function statusWords(status) {
  return {
    ok: "permissible and feasible",
    dispreferred: "permissible and feasible, but dispreferred by a soft norm",
    forbidden: "forbidden",
    infeasible: "permissible but infeasible",
  }[status];
}

function isSoft(kind) {
  return kind.startsWith("discouraged_") || kind.startsWith("preferred_");
}

/** The first object or person of the scene a reading's action names: its main argument. */
function mainObject(action) {
  const ids = new Set(scene ? referents().map((o) => o.id) : []);
  return (action.match(/[A-Za-z0-9_.-]+/g) ?? []).find((t) => ids.has(t)) ?? null;
}

function showDecision(d) {
  const facts = [
    ["Speech act", h("code", {}, d.speech_act)],
    ["Goal", d.goal ? h("code", {}, d.goal) : "none"],
  ];
  if (d.limits) facts.push(["Limits", `${d.limits.reason}: ${d.limits.simulated} of ${d.limits.readings} simulated`]);
  if (d.parse) facts.push(...parseFacts(d.parse));
  facts.push(["Versions", `norms ${d.norm_version}, actions ${d.library_version}`]);
  // An alternative offered after a refusal: the human may take it, decided afresh.
  const alternative = d.alternative
    ? h(
        "p",
        { class: "alternative" },
        "Offered instead: ",
        h("code", { id: "alternative" }, d.alternative),
        " ",
        h("button", { type: "button", id: "take-alternative" }, "Yes, do that instead"),
      )
    : null;
  let verdict = null;
  if (expected !== null) {
    verdict =
      d.utterance === expected
        ? h("p", { class: "hint" }, "✓ The paper's exact words for this case.")
        : h("p", { class: "hint" }, "The paper says: “", expected, "” (with its three norms installed).");
  }
  const parts = [
    h(
      "div",
      { class: "decision-head" },
      h("span", { class: `badge ${d.decision}`, id: "decision-kind" }, d.decision),
      h("span", {}, DECISION_WORDS[d.decision] ?? ""),
    ),
    h("blockquote", { class: "utterance", id: "utterance" }, h("span", { class: "who" }, "The robot says"), d.utterance),
    verdict,
    alternative,
    h("dl", { class: "facts" }, facts.map(([k, v]) => [h("dt", {}, k), h("dd", {}, v)])),
  ];
  $("decision").replaceChildren(...parts.filter(Boolean));
  if (alternative) {
    $("take-alternative").addEventListener("click", () =>
      takeAlternative({ button: $("take-alternative"), box: $("clarify-error") }),
    );
  }

  const offered = new Set(d.offered ?? []);
  const best = bestScore(d);
  $("readings-heading").hidden = d.interpretations.length === 0;
  $("readings").replaceChildren(
    ...d.interpretations.map((r) => {
      const status = readingStatus(r, best);
      return h(
        "li",
        { class: `reading ${status}` },
        h(
          "div",
          { class: "reading-head" },
          h("strong", {}, r.description),
          h("code", {}, r.action),
          r.permissible ? h("span", { class: "tag yes" }, "permissible") : h("span", { class: "tag no" }, "forbidden"),
          r.feasible ? h("span", { class: "tag yes" }, "feasible") : h("span", { class: "tag cant" }, "infeasible"),
          status === "dispreferred" ? h("span", { class: "tag soft" }, "dispreferred") : null,
          r.norm_score ? h("span", { class: "tag soft" }, `norm score ${r.norm_score > 0 ? "+" : ""}${r.norm_score}`) : null,
          r.action === d.goal ? h("span", { class: "tag offered" }, "goal") : null,
          offered.has(r.action) && r.action !== d.goal ? h("span", { class: "tag offered" }, "offered") : null,
        ),
        r.reasons.length
          ? h(
              "ul",
              {},
              r.reasons.map((reason) =>
                h(
                  "li",
                  { class: isSoft(reason.kind) ? "soft-reason" : "hard-reason" },
                  h("code", {}, reason.kind),
                  ` ${reason.words} — `,
                  h("code", {}, reason.detail),
                  reason.norm_id !== undefined ? ` (norm #${reason.norm_id}` : "",
                  reason.severity !== undefined ? `, severity ${reason.severity})` : reason.norm_id !== undefined ? ")" : "",
                ),
              ),
            )
          : null,
        h(
          "p",
          { class: "plan" },
          "Plan: ",
          r.plan.length ? h("code", {}, r.plan.join(" → ")) : "nothing simulated",
          r.score !== 1 ? ` · score ${r.score}` : "",
        ),
      );
    }),
  );

  marks = { status: {}, chosen: d.goal ? mainObject(d.goal) : null };
  for (const r of d.interpretations) {
    const id = mainObject(r.action);
    if (id && !(id in marks.status)) marks.status[id] = readingStatus(r, best);
  }
  if (scene) draw();
}

function showExchange(request, response) {
  $("exchange").hidden = false;
  $("request-json").textContent = JSON.stringify(request, null, 2);
  $("response-json").textContent = typeof response === "string" ? response : JSON.stringify(response, null, 2);
}

function fillCases() {
  $("case").append(
    ...PAPER.cases.map((c, i) => h("option", { value: String(i) }, `${c.text} — ${c.name}`)),
  );
}

function applyCase() {
  const c = PAPER.cases[Number($("case").value)];
  if (!$("case").value || !c) return;
  loadPreset(c.scene);
  $("text").value = c.text;
  const byForm = Boolean(c.directive.form);
  document.querySelector(`input[name="mode"][value="${byForm ? "form" : "action"}"]`).checked = true;
  showMode();
  for (const id of ["ref1-type", "ref1-props", "ref1-attrs", "ref1-id", "ref2-type", "ref2-id"]) $(id).value = "";
  if (byForm) {
    $("form").value = c.directive.form;
    $("bindings").value = Object.entries(c.directive.bindings)
      .map(([k, v]) => `${k}: ${v.map((b) => (typeof b === "string" ? b : `${b.id}=${b.score}`)).join(", ")}`)
      .join("\n");
  } else {
    $("verb").value = c.directive.action;
    const [first, second] = c.directive.arguments;
    if (first?.id) $("ref1-id").value = first.id;
    else if (first) $("ref1-type").value = first.type ?? "";
    if (second?.id) $("ref2-id").value = second.id;
    else if (second) $("ref2-type").value = second.type ?? "";
  }
  $("strategy").value = c.options?.strategy ?? "moral";
  $("single").value = c.options?.single_permissible ?? "assume";
  $("style").value = "diarc";
  $("soft-norms").value = "rank";
  $("alternatives").value = c.options?.alternatives ?? "";
  expected = c.expect.utterance;
}

// ---------------------------------------------------------------------------------------------
// The conversation: turns, the robot's open question, the focus

/** Every turn: how the human spoke (`kind`: words, structured, answer, choice, alternative), what
 *  they said, the request sent and the decision it got. Everything else is derived from these. */
let turns = [];

/**
 * The robot's open question, or null. `base`: the request whose decision asked it (never with an
 * answer); an answer is `base` sent again with the human's `answer`. `offered`: the readings that
 * decision named, among which a `choice` counts. `shown`: the decision that asks now: an answer
 * that narrows the question ("not the red one") asks again among the same readings, and the next
 * answer still answers the first question, which the service derives afresh from `base` (it keeps
 * no state). `direct`: `shown` is `base`'s own decision, so `{"choice": "alternative"}` takes the
 * alternative it offers.
 */
let pending = null;

const TURN_KINDS = ["words", "structured", "answer", "choice", "alternative"];
const ANSWER_KINDS = new Set(["answer", "choice", "alternative"]);
/** The answers in words the conversation's buttons send (CONTRACT.md, "Answers"). */
const NO = "no";
const NONE_OF_THEM = "none of them";

function withoutAnswer(request) {
  const { answer, ...rest } = request;
  return rest;
}

/** A decision that asks the human something: a question, a confirmation, an alternative offered. */
function asks(d) {
  return d.decision === "ask" || d.decision === "confirm" || Boolean(d.alternative);
}

/** The open question after `turn`, given the one before it. */
function questionAfter(before, turn) {
  const d = turn.response;
  if (!asks(d)) return null;
  if (before && turn.request.answer) {
    const named = [...d.offered, ...(d.alternative ? [d.alternative] : [])];
    if (before.offered.length && named.every((a) => before.offered.includes(a))) {
      return { base: before.base, offered: before.offered, shown: d, direct: false };
    }
    if (turn.kind === "answer") {
      // Words that were a whole directive ("Get the vase.") were decided as that directive.
      const base = withoutAnswer({ ...before.base, directive: { text: turn.said } });
      return { base, offered: d.offered, shown: d, direct: true };
    }
    return { base: before.base, offered: before.offered, shown: d, direct: false };
  }
  return { base: withoutAnswer(turn.request), offered: d.offered, shown: d, direct: true };
}

/** The open question after a list of turns, as it was when the last of them was answered. */
function replay(list) {
  let q = null;
  for (const t of list) q = questionAfter(q, t);
  return q;
}

/** Ids of a scene's objects and people that a term names, in order, each once. */
function idsIn(term, sceneOf) {
  const ids = new Set([...(sceneOf?.objects ?? []), ...(sceneOf?.people ?? [])].map((o) => o.id));
  return [...new Set((String(term).match(/[A-Za-z0-9_.-]+/g) ?? []).filter((t) => ids.has(t)))];
}

/** The focus after a turn: what its goal acts on (or the one reading it refused) first, then what
 *  was in focus before; a question, an explanation or words not understood leave it as it was. */
function focusAfter(focus, turn) {
  const d = turn.response;
  let term = d.goal;
  if (!term && d.decision === "refuse" && d.interpretations.length === 1) term = d.interpretations[0].action;
  if (!term) return focus;
  return [...new Set([...idsIn(term, turn.request.scene), ...focus])].slice(0, 6);
}

function currentFocus() {
  return list($("focus").value);
}

function setFocus(ids) {
  $("focus").value = ids.join(", ");
  $("focus").removeAttribute("aria-invalid");
}

/** How a reading of a decision is spoken: its description, else its term. */
function readingWords(d, action) {
  return d.interpretations.find((r) => r.action === action)?.description ?? action;
}

/** Problems of the conversation's box mark the box, where the form's would mark its words. */
const SAY_FIELD_CONTROLS = [["/directive/text", "say"], ...FIELD_CONTROLS];

/** Words from the human: the answer to the open question, else a new directive in words. */
async function answerInWords(text, { button, box, controls }) {
  if (pending) {
    return sendTurn({ kind: "answer", said: text }, { ...pending.base, answer: { text } }, { button, box, controls });
  }
  let request;
  try {
    request = buildRequest({ words: text });
  } catch (e) {
    showProblem(box, e, controls ?? FIELD_CONTROLS);
    return false;
  }
  return sendTurn({ kind: "words", said: text }, request, { button, box, controls });
}

async function say(event) {
  event.preventDefault();
  $("say").removeAttribute("aria-invalid");
  $("say-error").replaceChildren();
  const text = $("say").value.trim();
  if (!text) {
    const field = pending ? "/answer/text" : "/directive/text";
    const detail = pending ? "write the answer to the robot's question" : "write what the human says to the robot";
    showProblem($("say-error"), new Problem({ title: "Nothing said", detail, field }), SAY_FIELD_CONTROLS)?.focus();
    return;
  }
  const ok = await answerInWords(text, { button: $("say-button"), box: $("say-error"), controls: SAY_FIELD_CONTROLS });
  if (ok) $("say").value = "";
  $("say").focus();
}

/** A reading the open question offers, chosen by its button: `{"choice": N}`, N counted among the
 *  readings the question's request offers (the contract's choice form). */
async function chooseReading(action, { button, box }) {
  if (!pending) return false;
  const said = readingWords(pending.shown, action);
  const i = pending.offered.indexOf(action);
  // Only a question that an answer in words turned into another could offer a reading its
  // request does not: that reading is then answered in the words the robot used for it.
  const answer = i >= 0 ? { choice: i } : { text: said };
  return sendTurn({ kind: "choice", said }, { ...pending.base, answer }, { button, box, controls: SAY_FIELD_CONTROLS });
}

/** "Yes" to an alternative offered after a refusal: `{"choice": "alternative"}`, decided afresh. */
async function takeAlternative({ button, box }) {
  const alternative = pending?.shown.alternative;
  if (!alternative) {
    showProblem(box, new Problem({ title: "Nothing to take", detail: "no alternative is offered now (a new scene or conversation left it)" }), []);
    return false;
  }
  const said = "Yes, do that instead.";
  const opts = { button, box, controls: SAY_FIELD_CONTROLS };
  if (pending.direct) {
    return sendTurn({ kind: "alternative", said }, { ...pending.base, answer: { choice: "alternative" } }, opts);
  }
  const i = pending.offered.indexOf(alternative);
  if (i >= 0) return sendTurn({ kind: "alternative", said }, { ...pending.base, answer: { choice: i } }, opts);
  // Offered after an answer to an earlier question: the reading itself, as a logical form.
  return sendTurn({ kind: "alternative", said }, { ...pending.base, directive: { form: alternative } }, opts);
}

/** A term's arguments: `and(get(a),put(a,b))` → `["get(a)", "put(a,b)"]`. */
function termArgs(term) {
  const open = term.indexOf("(");
  if (open < 0 || !term.endsWith(")")) return [];
  const out = [];
  let depth = 0;
  let start = open + 1;
  for (let i = open + 1; i < term.length - 1; i++) {
    const c = term[i];
    if (c === "(") depth++;
    else if (c === ")") depth--;
    else if (c === "," && depth === 0) {
      out.push(term.slice(start, i));
      start = i + 1;
    }
  }
  out.push(term.slice(start, term.length - 1));
  return out;
}

/** A structured directive in one line: `get(vase)`, `get(mug); put(@0.0, sink)`, a form. */
function directiveSummary(dir) {
  const ref = (r) => {
    if (r.id !== undefined) return `#${r.id}`;
    if (r.step !== undefined) return `@${r.step}.${r.argument}`;
    const attrs = Object.entries(r.attributes ?? {}).map(([k, v]) => `${k}=${v}`);
    return [r.type, ...(r.properties ?? []), ...attrs].filter(Boolean).join(" ");
  };
  const step = (st) => `${st.action}(${(st.arguments ?? []).map(ref).join(", ")})${st.joiner ? ` joiner=${st.joiner}` : ""}`;
  if (dir.steps) return dir.steps.map(step).join("; ");
  if (dir.form) {
    const b = Object.entries(dir.bindings ?? {}).map(([k, v]) => `${k}: ${v.map((x) => (typeof x === "string" ? x : x.id)).join(", ")}`);
    return `${dir.form}${b.length ? ` with ${b.join("; ")}` : ""}`;
  }
  if (dir.action) return step(dir);
  return dir.text ?? "";
}

/** A task's steps: the goal's `and(…)` when it has one, else the steps the words were read as. */
function taskSteps(d) {
  let items = null;
  if (d.goal) {
    const act = termArgs(d.goal)[1];
    if (act?.startsWith("and(")) items = termArgs(act).map((a) => h("code", {}, a));
  }
  if (!items && (d.parse?.steps?.length ?? 0) > 1) {
    items = d.parse.steps.map((st) => [
      h("code", {}, st.form),
      st.references.length ? ` ${st.references.map((r) => `“${r.words}”`).join(", ")}` : "",
    ]);
  }
  if (!items) return null;
  const plan = d.goal ? d.interpretations.find((r) => r.action === d.goal)?.plan : null;
  return h(
    "div",
    { class: "turn-task" },
    h("span", { class: "meta" }, d.goal ? "The task's steps:" : "Steps as read:"),
    h("ol", { class: "turn-steps" }, items.map((x) => h("li", {}, x))),
    plan?.length ? h("p", { class: "meta" }, "Plan: ", h("code", {}, plan.join(" → "))) : null,
  );
}

function humanSaid(t) {
  const r = t.request;
  if (t.kind === "structured") {
    return h(
      "p",
      { class: "turn-said" },
      r.directive.text ? [h("q", {}, r.directive.text), " "] : null,
      h("code", { class: "structured" }, directiveSummary(r.directive)),
    );
  }
  if (t.kind === "choice") return h("p", { class: "turn-said" }, "Chose: ", h("strong", {}, t.said));
  return h("p", { class: "turn-said" }, h("q", {}, t.said));
}

const HOW = {
  words: "said",
  structured: "directed, structured",
  answer: "answered",
  choice: "answered by choosing",
  alternative: "took the alternative",
};

function answerButtons(d) {
  const buttons = [];
  if (d.decision === "ask") {
    for (const a of d.offered) {
      buttons.push(h("button", { type: "button", "data-answer": "choice", "data-action": a }, readingWords(d, a)));
    }
    buttons.push(h("button", { type: "button", "data-answer": "text", "data-text": NONE_OF_THEM }, "None of them"));
  } else if (d.decision === "confirm" && d.offered.length) {
    const a = d.offered[0];
    buttons.push(
      h("button", { type: "button", "data-answer": "choice", "data-action": a }, `Yes, ${readingWords(d, a)}`),
      h("button", { type: "button", "data-answer": "text", "data-text": NO }, "No"),
    );
  }
  if (d.alternative) {
    buttons.push(h("button", { type: "button", "data-answer": "alternative" }, "Yes, take the alternative"));
  }
  if (!buttons.length) return null;
  return h(
    "div",
    { class: "answer-buttons", role: "group", "aria-label": "Answer the robot's question" },
    h("span", { class: "meta" }, d.decision === "ask" ? "Answer by choosing a reading:" : "Answer:"),
    buttons,
  );
}

function turnItem(t, i, open) {
  const r = t.request;
  const d = t.response;
  const speaker = r.speaker ?? "human";
  const human = h(
    "div",
    { class: "said human" },
    h("span", { class: "who" }, `${speaker} ${HOW[t.kind] ?? t.kind}`, r.speaker_roles?.length ? ` (as ${r.speaker_roles.join(", ")})` : ""),
    humanSaid(t),
    r.answer ? h("p", { class: "meta" }, "sent as ", h("code", { class: "turn-answer" }, `"answer": ${JSON.stringify(r.answer)}`), " with the question's request") : null,
    !r.answer && r.focus?.length ? h("p", { class: "meta" }, "focus ", h("code", { class: "turn-focus" }, r.focus.join(", "))) : null,
  );
  const robot = h(
    "div",
    { class: "said robot" },
    h("span", { class: "who" }, d.parse?.addressee ? `robot, addressed as “${d.parse.addressee}”` : "robot"),
    h(
      "p",
      { class: "turn-reply" },
      h("span", { class: `badge ${d.decision} turn-decision` }, d.decision),
      " ",
      h("span", { class: "turn-utterance" }, d.utterance),
    ),
    taskSteps(d),
    d.goal ? h("p", { class: "meta" }, "goal ", h("code", { class: "turn-goal" }, d.goal)) : null,
    open ? answerButtons(d) : null,
  );
  return h("li", { class: `turn ${t.kind}`, "data-turn": String(i) }, human, robot);
}

/** Shows the turns. The transcript is a live log: a new turn is appended (and only it is
 *  announced), and only the last turn holds the open question's buttons; `rebuild` draws it anew
 *  (a new conversation, a transcript loaded). */
function renderTranscript({ rebuild = false } = {}) {
  const box = $("transcript");
  const open = pending ? pending.shown : null;
  const shown = box.querySelectorAll("li.turn").length;
  const isOpen = (i) => i === turns.length - 1 && turns[i].response === open;
  if (!rebuild && turns.length && (shown === turns.length || shown === turns.length - 1)) {
    box.querySelector(".turn-empty")?.remove();
    for (const el of box.querySelectorAll(".answer-buttons")) el.remove();
    const last = turns.length - 1;
    if (shown === last) {
      box.append(turnItem(turns[last], last, isOpen(last)));
    } else if (isOpen(last)) {
      const buttons = answerButtons(turns[last].response);
      if (buttons) box.querySelector("li.turn:last-child .said.robot").append(buttons);
    }
  } else {
    box.replaceChildren(...turns.map((t, i) => turnItem(t, i, isOpen(i))));
    if (!turns.length) {
      box.append(h("li", { class: "turn-empty" }, "No turns yet: say something to the robot below, or compose a directive."));
    }
  }
  box.scrollTop = box.scrollHeight;
  $("say-form").classList.toggle("answering", Boolean(pending));
  $("say-hint").textContent = pending
    ? "The robot asked: what you say next answers it (its question's request is sent again with your \"answer\"); a whole new directive is decided as one."
    : "Words are read as a new directive, against the scene, the norms and the verbs.";
}

function resetDecision() {
  $("decision").replaceChildren(h("p", { class: "hint" }, "Nothing asked yet."));
  $("readings").replaceChildren();
  $("readings-heading").hidden = true;
  $("exchange").hidden = true;
  marks = { status: {}, chosen: null };
  if (scene) draw();
}

function newConversation() {
  turns = [];
  pending = null;
  lastRequest = null;
  setFocus([]);
  for (const id of ["say-error", "transcript-error", "clarify-error"]) $(id).replaceChildren();
  resetDecision();
  renderTranscript({ rebuild: true });
  $("transcript-status").textContent = "A new conversation: no turns, nothing in focus.";
  $("say").focus();
}

// ---------------------------------------------------------------------------------------------
// A transcript as a file: exported with its scene, settings, focus and versions; loaded whole or
// not at all

const TRANSCRIPT_FORMAT = "scruple-playground-transcript";
const MAX_TURNS = 1000;

function transcriptDocument() {
  const last = turns.at(-1)?.response;
  return {
    format: TRANSCRIPT_FORMAT,
    version: 1,
    exported_at: new Date().toISOString(),
    norm_version: last?.norm_version ?? null,
    library_version: last?.library_version ?? null,
    scene,
    settings: settings(),
    focus: currentFocus(),
    norms,
    turns: turns.map(({ kind, said, request, response }) => ({ kind, said, request, response })),
  };
}

function exportTranscript() {
  $("transcript-error").replaceChildren();
  if (!scene) {
    showProblem($("transcript-error"), new Problem({ title: "Nothing to export", detail: "the scene does not parse: fix it first", field: "/scene" }), FIELD_CONTROLS);
    return;
  }
  const doc = transcriptDocument();
  const name = `scruple-transcript-${doc.exported_at.replace(/[-:]/g, "").replace(/\..*/, "")}.json`;
  const url = URL.createObjectURL(new Blob([`${JSON.stringify(doc, null, 2)}\n`], { type: "application/json" }));
  const a = h("a", { href: url, download: name, hidden: true });
  document.body.append(a);
  a.click();
  a.remove();
  setTimeout(() => URL.revokeObjectURL(url), 10_000);
  $("transcript-status").textContent = `Exported ${doc.turns.length} turn${doc.turns.length === 1 ? "" : "s"} as ${name}.`;
}

/** Checks a transcript file whole and returns it; a Problem naming the first fault otherwise. */
function checkTranscript(text, fileName) {
  const bad = (detail, field) =>
    new Problem({ title: "Not a transcript this page can load", detail: `${fileName}: ${detail}`, field });
  let doc;
  try {
    doc = JSON.parse(text);
  } catch (e) {
    throw bad(`not JSON (${e.message})`);
  }
  const isObject = (v) => v !== null && typeof v === "object" && !Array.isArray(v);
  const isText = (v) => typeof v === "string";
  const isVersion = (v) => v === null || v === undefined || Number.isInteger(v);
  if (!isObject(doc)) throw bad("a transcript is a JSON object", "/");
  if (doc.format !== TRANSCRIPT_FORMAT) throw bad(`"format" must be "${TRANSCRIPT_FORMAT}"`, "/format");
  if (doc.version !== 1) throw bad(`version ${JSON.stringify(doc.version)} is not one this page reads (1)`, "/version");
  if (!isVersion(doc.norm_version)) throw bad("norm_version must be an integer", "/norm_version");
  if (!isVersion(doc.library_version)) throw bad("library_version must be an integer", "/library_version");
  const sceneOf = (value, field) => {
    if (!isObject(value)) throw bad("the scene must be an object", field);
    try {
      return parseScene(JSON.stringify(value));
    } catch (e) {
      throw bad(`the scene cannot be drawn: ${e.problem?.detail ?? e.message}`, field + (e.problem?.field ?? "").replace(/^\/scene/, ""));
    }
  };
  const drawn = sceneOf(doc.scene, "/scene");
  const st = doc.settings;
  if (!isObject(st)) throw bad("settings must be an object", "/settings");
  if (!isText(st.speaker) || !st.speaker.trim()) throw bad("settings.speaker must be a name", "/settings/speaker");
  if (!Array.isArray(st.speaker_roles) || !st.speaker_roles.every(isText)) {
    throw bad("settings.speaker_roles must be a list of words", "/settings/speaker_roles");
  }
  if (!isText(st.context)) throw bad("settings.context must be a word", "/settings/context");
  if (!isObject(st.options)) throw bad("settings.options must be an object", "/settings/options");
  for (const [key, control] of Object.entries(OPTION_CONTROLS)) {
    const value = st.options[key];
    if (value === undefined) continue;
    const allowed = [...$(control).options].map((o) => o.value).filter(Boolean);
    if (!allowed.includes(value)) throw bad(`options.${key} must be one of ${allowed.join(", ")}`, `/settings/options/${key}`);
  }
  const ids = new Set([...drawn.objects, ...drawn.people].map((o) => o.id));
  if (!Array.isArray(doc.focus)) throw bad("focus must be a list of ids", "/focus");
  doc.focus.forEach((id, i) => {
    if (!isText(id) || !ids.has(id)) throw bad(`focus names ${JSON.stringify(id)}, which the scene does not hold`, `/focus/${i}`);
  });
  if (!Array.isArray(doc.turns)) throw bad("turns must be a list", "/turns");
  if (doc.turns.length > MAX_TURNS) throw bad(`more than ${MAX_TURNS} turns`, "/turns");
  doc.turns.forEach((t, i) => {
    const at = `/turns/${i}`;
    if (!isObject(t)) throw bad(`turn ${i + 1} must be an object`, at);
    if (!TURN_KINDS.includes(t.kind)) throw bad(`turn ${i + 1}'s kind must be one of ${TURN_KINDS.join(", ")}`, `${at}/kind`);
    if (!isText(t.said)) throw bad(`turn ${i + 1} must say what the human said`, `${at}/said`);
    const r = t.request;
    if (!isObject(r)) throw bad(`turn ${i + 1} has no request`, `${at}/request`);
    if (!isObject(r.directive)) throw bad(`turn ${i + 1}'s request has no directive`, `${at}/request/directive`);
    sceneOf(r.scene, `${at}/request/scene`);
    const answered = r.answer !== undefined;
    if (answered && !isObject(r.answer)) throw bad(`turn ${i + 1}'s answer must be an object`, `${at}/request/answer`);
    if ((t.kind === "answer" || t.kind === "choice") && !answered) throw bad(`turn ${i + 1} is an answer but sends none`, `${at}/request/answer`);
    if ((t.kind === "words" || t.kind === "structured") && answered) throw bad(`turn ${i + 1} is a directive but sends an answer`, `${at}/request/answer`);
    if (t.kind === "answer" && r.answer.text !== t.said) throw bad(`turn ${i + 1}'s answer is not what it says was said`, `${at}/request/answer/text`);
    const d = t.response;
    if (!isObject(d)) throw bad(`turn ${i + 1} has no decision`, `${at}/response`);
    if (!isText(d.decision) || !d.decision) throw bad(`turn ${i + 1}'s decision is missing`, `${at}/response/decision`);
    for (const key of ["utterance", "speech_act"]) {
      if (!isText(d[key])) throw bad(`turn ${i + 1}'s ${key} must be text`, `${at}/response/${key}`);
    }
    if (!(d.goal === null || d.goal === undefined || isText(d.goal))) throw bad(`turn ${i + 1}'s goal must be a term`, `${at}/response/goal`);
    if (!(d.alternative === null || d.alternative === undefined || isText(d.alternative))) {
      throw bad(`turn ${i + 1}'s alternative must be a term`, `${at}/response/alternative`);
    }
    if (!Array.isArray(d.offered) || !d.offered.every(isText)) throw bad(`turn ${i + 1}'s offered must be a list of terms`, `${at}/response/offered`);
    if (!Array.isArray(d.interpretations)) throw bad(`turn ${i + 1}'s interpretations must be a list`, `${at}/response/interpretations`);
    d.interpretations.forEach((x, j) => {
      const ok = isObject(x) && isText(x.action) && isText(x.description) && typeof x.permissible === "boolean" &&
        typeof x.feasible === "boolean" && Array.isArray(x.reasons) && Array.isArray(x.plan);
      if (!ok) throw bad(`turn ${i + 1}'s reading ${j + 1} is not a reading`, `${at}/response/interpretations/${j}`);
    });
    if (!Number.isInteger(d.norm_version) || !Number.isInteger(d.library_version)) {
      throw bad(`turn ${i + 1}'s decision lacks its versions`, `${at}/response/norm_version`);
    }
  });
  return doc;
}

/** The form controls of `settings().options`, by key. */
const OPTION_CONTROLS = {
  strategy: "strategy",
  single_permissible: "single",
  style: "style",
  soft_norms: "soft-norms",
  alternatives: "alternatives",
};

async function loadTranscript(file) {
  $("transcript-error").replaceChildren();
  let doc;
  try {
    doc = checkTranscript(await file.text(), file.name);
  } catch (e) {
    showProblem($("transcript-error"), e, []);
    $("transcript-status").textContent = "Nothing was loaded: the conversation is as it was.";
    return;
  }
  // Checked whole: now everything at once.
  $("scene-json").value = JSON.stringify(doc.scene, null, 2);
  marks = { status: {}, chosen: null };
  const st = doc.settings;
  $("speaker").value = st.speaker;
  $("speaker-roles").value = st.speaker_roles.join(", ");
  $("context").value = st.context;
  for (const [key, control] of Object.entries(OPTION_CONTROLS)) {
    $(control).value = st.options[key] ?? (key === "alternatives" ? "" : $(control).options[0].value);
  }
  expected = null;
  turns = doc.turns.map(({ kind, said, request, response }) => ({ kind, said, request, response }));
  pending = replay(turns);
  sceneEdited();
  setFocus(doc.focus);
  for (const id of ["say-error", "clarify-error"]) $(id).replaceChildren();
  const last = turns.at(-1);
  if (last) {
    lastRequest = last.request;
    showDecision(last.response);
    showExchange(last.request, last.response);
  } else {
    resetDecision();
  }
  renderTranscript({ rebuild: true });
  const versions = doc.norm_version === null ? "" : ` (norms version ${doc.norm_version}, actions ${doc.library_version} when exported)`;
  $("transcript-status").textContent = `Loaded ${turns.length} turn${turns.length === 1 ? "" : "s"} from ${file.name}${versions}.`;
}

// ---------------------------------------------------------------------------------------------
// People: scene.people as rows, written back into the scene JSON

function renderPeople() {
  const body = $("people-body");
  const people = scene?.people ?? [];
  body.replaceChildren(
    ...people.map((p, i) => {
      const n = i + 1;
      const cell = (field, value, label) =>
        h("td", {}, h("input", { type: "text", class: `person-${field}`, value, "aria-label": `Person ${n} ${label}`, autocomplete: "off", spellcheck: "false" }));
      return h(
        "tr",
        { "data-person": String(i) },
        cell("id", p.id, "id"),
        cell("names", (p.names ?? []).join(", "), "names"),
        cell("roles", (p.roles ?? []).join(", "), "roles"),
        cell("position", p.position.join(", "), "position"),
        h("td", {}, h("button", { type: "button", class: "danger", "data-remove-person": String(i), "aria-label": `Remove person ${n} (${p.id})` }, "Remove")),
      );
    }),
  );
  if (!people.length) {
    body.append(h("tr", {}, h("td", { colspan: 5, class: "empty" }, "Nobody: add a person, or give the scene JSON a \"people\" list.")));
  }
}

/** The people as the rows say; a Problem with the input at fault otherwise. */
function peopleFromRows() {
  const objectIds = new Set(scene.objects.map((o) => o.id));
  const seen = new Set();
  return [...$("people-body").querySelectorAll("tr[data-person]")].map((row, i) => {
    const input = (f) => row.querySelector(`.person-${f}`);
    const bad = (el, detail) => Object.assign(new Problem({ title: "Check the people", detail, field: `/scene/people/${i}` }), { input: el });
    const id = input("id").value.trim();
    if (!/^\S+$/.test(id)) throw bad(input("id"), `person ${i + 1} needs an id, one word`);
    if (objectIds.has(id) || seen.has(id)) throw bad(input("id"), `the id “${id}” is already taken`);
    seen.add(id);
    const position = input("position").value.split(/[\s,]+/).filter(Boolean).map(Number);
    if (position.length !== 3 || position.some((x) => !Number.isFinite(x))) {
      throw bad(input("position"), `person ${i + 1}'s position is three numbers: x, y, z`);
    }
    const person = { ...(scene.people[i] ?? {}), id, position };
    const names = list(input("names").value);
    const roles = list(input("roles").value);
    delete person.names;
    delete person.roles;
    if (names.length) person.names = names;
    if (roles.length) person.roles = roles;
    return { id: person.id, ...person };
  });
}

function writePeople(people, { rerender }) {
  $("scene-json").value = JSON.stringify({ ...scene, people }, null, 2);
  sceneEdited({ fromPeople: !rerender });
}

function peopleEdited() {
  for (const el of $("people-body").querySelectorAll("[aria-invalid]")) el.removeAttribute("aria-invalid");
  if (!scene) return;
  try {
    const people = peopleFromRows();
    writePeople(people, { rerender: false });
    // The rows stay (the one being typed in keeps its focus); their remove buttons follow the ids.
    for (const b of $("people-body").querySelectorAll("button[data-remove-person]")) {
      const i = Number(b.dataset.removePerson);
      b.setAttribute("aria-label", `Remove person ${i + 1} (${people[i].id})`);
    }
    $("people-status").textContent = "People written to the scene.";
  } catch (e) {
    if (!(e instanceof Problem)) throw e;
    e.input?.setAttribute("aria-invalid", "true");
    $("people-status").textContent = `Not written to the scene: ${e.problem.detail}.`;
  }
}

function addPerson() {
  if (!scene) return;
  const taken = new Set(referents().map((o) => o.id));
  let n = scene.people.length + 1;
  while (taken.has(`person${n}`)) n++;
  writePeople([...scene.people, { id: `person${n}`, names: [], roles: [], position: [0.6, -0.5, 0.8] }], { rerender: true });
  $("people-status").textContent = `Added person${n}: give them names and roles.`;
  $("people-body").querySelector("tr[data-person]:last-child .person-names")?.focus();
}

function removePerson(i) {
  if (!scene) return;
  const gone = scene.people[i];
  writePeople(scene.people.filter((_, j) => j !== i), { rerender: true });
  $("people-status").textContent = `Removed ${gone?.id ?? "the person"}.`;
  $("add-person").focus();
}

// ---------------------------------------------------------------------------------------------
// Verbs: the action library, listed and edited as JSON

let verbs = [];

async function loadVerbs() {
  try {
    verbs = await call("GET", "/v1/actions");
    if (verbsProblem) {
      $("verb-error").replaceChildren();
      verbsProblem = false;
    }
  } catch (e) {
    verbs = [];
    showProblem($("verb-error"), e, []);
    verbsProblem = true;
  }
  const names = verbs.length ? verbs.map((a) => a.name) : ["get", "pointTo", "destroy", "steal", "put"];
  $("verbs").replaceChildren(...names.map((v) => h("option", { value: v })));
  renderVerbs();
}
/** Whether the problem shown under the verbs is one of reading them (cleared by the next read). */
let verbsProblem = false;

function renderVerbs() {
  const body = $("verbs-body");
  if (!verbs.length) {
    body.replaceChildren(h("tr", {}, h("td", { colspan: 3, class: "empty" }, "No verbs read.")));
    return;
  }
  body.replaceChildren(
    ...verbs.map((v) =>
      h(
        "tr",
        {},
        h("td", {}, h("code", {}, `${v.name}(${(v.parameters ?? []).join(",")})`)),
        h("td", { class: "verb-words" }, (v.words ?? []).join(", ") || h("span", { class: "hint" }, "no words")),
        h("td", {}, h("button", { type: "button", "data-verb": v.name, "aria-label": `Edit verb ${v.name}` }, "Edit")),
      ),
    ),
  );
}

function editVerb(name) {
  const verb = verbs.find((v) => v.name === name);
  if (!verb) return;
  const { name: _, ...body } = verb;
  clearInvalid($("verb-form"));
  $("verb-error").replaceChildren();
  verbsProblem = false;
  $("verb-name").value = name;
  $("verb-json").value = JSON.stringify(body, null, 2);
  $("verbs-status").textContent = `Editing ${name}: save to replace it.`;
  $("verb-json").focus();
}

/** The value a JSON Pointer names in `text`, when the text is JSON and holds it. */
function pointerValue(text, pointer) {
  try {
    let v = JSON.parse(text);
    for (const raw of pointer.split("/").slice(1)) {
      const key = raw.replace(/~1/g, "/").replace(/~0/g, "~");
      if (v === null || typeof v !== "object" || !(key in v)) return undefined;
      v = v[key];
    }
    return v;
  } catch {
    return undefined;
  }
}

async function saveVerb(event) {
  event.preventDefault();
  clearInvalid($("verb-form"));
  $("verb-error").replaceChildren();
  verbsProblem = false;
  const name = $("verb-name").value.trim();
  const text = $("verb-json").value;
  const button = $("save-verb");
  button.disabled = true;
  try {
    if (!name) throw new Problem({ title: "Check the verb", detail: "name the verb to save", field: "/name" });
    // Sent as written: what is wrong with it is the service's to say, at its field.
    const stored = await call("PUT", `/v1/actions/${encodeURIComponent(name)}`, text, { raw: true });
    await loadVerbs();
    $("verbs-status").textContent = `Saved verb ${stored?.name ?? name}.`;
  } catch (e) {
    const control = showProblem($("verb-error"), e, VERB_FIELD_CONTROLS);
    const field = e instanceof Problem ? e.problem.field : null;
    const there = field && field !== "/name" ? pointerValue(text, field) : undefined;
    if (there !== undefined) {
      $("verb-error").querySelector(".problem")?.append(h("p", {}, "There: ", h("code", { class: "verb-there" }, JSON.stringify(there))));
    }
    control?.focus();
  } finally {
    button.disabled = false;
  }
}

// ---------------------------------------------------------------------------------------------
// Norms

let norms = [];

/** Whether the problem shown under the norms is one of reading them (cleared by the next read). */
let normsProblem = false;

async function refreshNorms() {
  try {
    norms = await call("GET", "/v1/norms");
    if (normsProblem) $("norm-error").replaceChildren();
    normsProblem = false;
    renderNorms();
  } catch (e) {
    showProblem($("norm-error"), e, NORM_FIELD_CONTROLS);
    normsProblem = true;
  }
}

function renderNorms() {
  const body = $("norms-body");
  if (!norms.length) {
    body.replaceChildren(h("tr", {}, h("td", { colspan: 6, class: "empty" }, "No norms: everything is permissible.")));
    return;
  }
  body.replaceChildren(
    ...norms.map((n) =>
      h(
        "tr",
        {},
        h("td", {}, String(n.id)),
        h(
          "td",
          { class: "norm" },
          h("span", { class: `kind ${isSoft(n.kind) ? "soft" : "hard"}` }, n.kind.replace("_", " ")),
          h("code", { class: "term" }, n.action ?? n.state ?? ""),
          n.when?.length ? h("span", { class: "when" }, "when ", h("code", {}, n.when.join(", "))) : null,
        ),
        h(
          "td",
          {},
          n.context ?? "any",
          n.roles?.length ? h("span", { class: "roles" }, `for ${n.roles.join(", ")}`) : null,
          n.exempt_roles?.length ? h("span", { class: "roles" }, `not for ${n.exempt_roles.join(", ")}`) : null,
        ),
        h("td", {}, String(n.severity)),
        h("td", {}, n.note ?? ""),
        h(
          "td",
          {},
          h("button", { type: "button", class: "danger", "data-norm": n.id, "aria-label": `Delete norm ${n.id}` }, "Delete"),
        ),
      ),
    ),
  );
}

async function deleteNorm(id) {
  $("norm-error").replaceChildren();
  try {
    await call("DELETE", `/v1/norms/${id}`);
    $("norms-status").textContent = `Deleted norm ${id}.`;
    await refreshNorms();
    $("refresh-norms").focus();
  } catch (e) {
    showProblem($("norm-error"), e, NORM_FIELD_CONTROLS);
  }
}

function normKindChanged() {
  const action = $("norm-kind").value.endsWith("_action");
  $("norm-term-label").textContent = action ? "Action" : "State";
  $("norm-term").placeholder = action ? "destroy" : "did(self,get(object3))";
}

async function addNorm(event) {
  event.preventDefault();
  const form = $("norm-form");
  clearInvalid(form);
  $("norm-error").replaceChildren();
  const kind = $("norm-kind").value;
  const norm = { kind };
  norm[kind.endsWith("_action") ? "action" : "state"] = $("norm-term").value.trim();
  const when = $("norm-when").value.split("\n").map((l) => l.trim()).filter(Boolean);
  if (when.length) norm.when = when;
  const context = $("norm-context").value.trim();
  if (context) norm.context = context;
  const roles = list($("norm-roles").value);
  if (roles.length) norm.roles = roles;
  const exempt = list($("norm-exempt").value);
  if (exempt.length) norm.exempt_roles = exempt;
  const severity = $("norm-severity").value.trim();
  if (severity) norm.severity = Number(severity);
  const note = $("norm-note").value.trim();
  if (note) norm.note = note;
  try {
    const stored = await call("POST", "/v1/norms", norm);
    $("norms-status").textContent = `Added norm ${stored.id}: ${stored.kind} ${stored.action ?? stored.state}.`;
    for (const id of ["norm-term", "norm-when", "norm-note", "norm-roles", "norm-exempt"]) $(id).value = "";
    await refreshNorms();
  } catch (e) {
    showProblem($("norm-error"), e, NORM_FIELD_CONTROLS)?.focus();
  }
}

/** The paper's norms, in its order, skipping any already stored with the same kind and term. */
async function addPaperNorms() {
  $("norm-error").replaceChildren();
  const key = (n) => `${n.kind} ${n.action ?? n.state} ${n.context ?? ""}`;
  const have = new Set(norms.map(key));
  let added = 0;
  try {
    for (const n of PAPER.norms) {
      if (have.has(key(n))) continue;
      await call("POST", "/v1/norms", n);
      added++;
    }
    $("norms-status").textContent = added ? `Added ${added} of the paper's norms.` : "The paper's norms are all there.";
  } catch (e) {
    showProblem($("norm-error"), e, NORM_FIELD_CONTROLS);
  }
  await refreshNorms();
}

// ---------------------------------------------------------------------------------------------
// Start

async function health() {
  try {
    const r = await call("GET", "/healthz");
    $("health").textContent = r.status;
  } catch (e) {
    $("health").textContent = e instanceof Problem ? e.problem.title : "unreachable";
  }
}

function start() {
  let timer = null;
  $("load-preset").addEventListener("click", () => loadPreset($("preset").value));
  $("scene-json").addEventListener("input", () => {
    clearTimeout(timer);
    timer = setTimeout(sceneEdited, 250);
  });
  for (const radio of document.querySelectorAll('input[name="mode"]')) radio.addEventListener("change", showMode);
  $("case").addEventListener("change", applyCase);
  $("clarify-form").addEventListener("input", (e) => {
    if (e.target.id !== "case") expected = null;
    if (e.target.hasAttribute("aria-invalid")) e.target.removeAttribute("aria-invalid");
  });
  $("clarify-form").addEventListener("submit", clarify);
  $("norm-form").addEventListener("submit", addNorm);
  // The token is kept in the page only (never stored); with it the page reads again what a
  // service with reader tokens refused it. Enter in its field must not reload the page.
  let tokenTimer = null;
  const readAgain = () => {
    clearTimeout(tokenTimer);
    health();
    refreshNorms();
    loadVerbs();
  };
  $("token").addEventListener("input", () => {
    clearTimeout(tokenTimer);
    tokenTimer = setTimeout(readAgain, 400);
  });
  $("token-form").addEventListener("submit", (e) => {
    e.preventDefault();
    readAgain();
  });
  // The conversation.
  $("say-form").addEventListener("submit", say);
  $("say").addEventListener("input", () => $("say").removeAttribute("aria-invalid"));
  $("transcript").addEventListener("click", (e) => {
    const b = e.target.closest("button[data-answer]");
    if (!b) return;
    const opts = { button: b, box: $("say-error"), controls: SAY_FIELD_CONTROLS };
    let answered;
    if (b.dataset.answer === "choice") answered = chooseReading(b.dataset.action, opts);
    else if (b.dataset.answer === "alternative") answered = takeAlternative(opts);
    else answered = answerInWords(b.dataset.text, opts);
    // The buttons go with the question: the keyboard goes back to the box.
    answered.then(() => $("say").focus());
  });
  $("clear-focus").addEventListener("click", () => {
    setFocus([]);
    $("transcript-status").textContent = "Focus cleared: “it” means nothing until a decision acts on something.";
    $("focus").focus();
  });
  $("focus").addEventListener("input", () => $("focus").removeAttribute("aria-invalid"));
  $("new-conversation").addEventListener("click", newConversation);
  $("export-transcript").addEventListener("click", exportTranscript);
  $("load-transcript-button").addEventListener("click", () => $("load-transcript").click());
  $("load-transcript").addEventListener("change", () => {
    const file = $("load-transcript").files[0];
    $("load-transcript").value = "";
    if (file) loadTranscript(file);
  });
  // People.
  let peopleTimer = null;
  $("people-body").addEventListener("input", () => {
    clearTimeout(peopleTimer);
    peopleTimer = setTimeout(peopleEdited, 250);
  });
  $("people-body").addEventListener("click", (e) => {
    const b = e.target.closest("button[data-remove-person]");
    if (b) removePerson(Number(b.dataset.removePerson));
  });
  $("add-person").addEventListener("click", addPerson);
  // Verbs.
  $("verb-form").addEventListener("submit", saveVerb);
  $("verb-json").addEventListener("keydown", (e) => {
    if (e.key === "Enter" && (e.ctrlKey || e.metaKey)) {
      e.preventDefault();
      $("verb-form").requestSubmit();
    }
  });
  $("verbs-body").addEventListener("click", (e) => {
    const b = e.target.closest("button[data-verb]");
    if (b) editVerb(b.dataset.verb);
  });
  $("refresh-verbs").addEventListener("click", loadVerbs);
  $("norm-kind").addEventListener("change", normKindChanged);
  $("refresh-norms").addEventListener("click", refreshNorms);
  $("paper-norms").addEventListener("click", addPaperNorms);
  $("norms-body").addEventListener("click", (e) => {
    const button = e.target.closest("button[data-norm]");
    if (button) deleteNorm(button.dataset.norm);
  });
  fillCases();
  normKindChanged();
  loadPreset("lab");
  renderTranscript({ rebuild: true });
  document.body.dataset.ready = "true";
  health();
  loadVerbs();
  refreshNorms();
}

start();

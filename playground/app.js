// Scruple playground: a plain ES module, no build step, no dependencies.
//
// The page is a client of the public REST API and nothing more: every decision, norm and verb it
// shows comes from /v1/clarify, /v1/norms and /v1/actions, and every failure is the service's own
// problem+json, shown as sent. It never decides anything itself.

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

const PRESETS = { lab: PAPER.scenes.lab, office: PAPER.scenes.office, reach: REACH_DEMO, household: HOUSEHOLD };

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
  ["/speaker", "speaker"],
  ["/context", "context"],
  ["/options/strategy", "strategy"],
  ["/options/single_permissible", "single"],
  ["/options/style", "style"],
  ["/options/soft_norms", "soft-norms"],
  ["/options/alternatives", "alternatives"],
];
const NORM_FIELD_CONTROLS = [
  ["/kind", "norm-kind"],
  ["/action", "norm-term"],
  ["/state", "norm-term"],
  ["/when", "norm-when"],
  ["/context", "norm-context"],
  ["/severity", "norm-severity"],
  ["/note", "norm-note"],
];

// ---------------------------------------------------------------------------------------------
// HTTP

async function call(method, path, body) {
  const headers = { accept: "application/json, application/problem+json" };
  if (body !== undefined) headers["content-type"] = "application/json";
  const token = $("admin-token").value.trim();
  if (token && method !== "GET") headers.authorization = `Bearer ${token}`;
  let response;
  try {
    response = await fetch(path, {
      method,
      headers,
      body: body === undefined ? undefined : JSON.stringify(body),
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
  sceneEdited();
}

/** Parses the textarea; on success draws it, otherwise keeps the last drawing and says why. */
function sceneEdited() {
  const status = $("scene-json-status");
  try {
    scene = parseScene($("scene-json").value);
    $("scene-json").removeAttribute("aria-invalid");
    const people = scene.people.length;
    status.textContent = `Drawn: ${scene.objects.length} object${scene.objects.length === 1 ? "" : "s"}` +
      (people ? `, ${people} ${people === 1 ? "person" : "people"}.` : ".");
    draw();
    fillSceneLists();
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

function buildRequest() {
  if (!scene) {
    throw new Problem({ title: "No scene", detail: $("scene-json-status").textContent, field: "/scene" });
  }
  const directive = {};
  const text = $("text").value.trim();
  if (mode() === "action") {
    directive.action = $("verb").value.trim();
    directive.arguments = [reference("ref1", 0), reference("ref2", 1)].filter(Boolean);
  } else if (mode() === "form") {
    directive.form = $("form").value.trim();
    directive.bindings = bindings($("bindings").value);
  } else if (mode() === "steps") {
    directive.steps = steps($("steps").value);
  } else if (!text) {
    throw new Problem({ title: "Check the form", detail: "write the human's words to send them alone", field: "/directive/text" });
  }
  if (text) directive.text = text;
  const body = {
    speaker: $("speaker").value.trim() || "human",
    directive,
    scene,
    context: $("context").value.trim() || "default",
    options: {
      strategy: $("strategy").value,
      single_permissible: $("single").value,
      style: $("style").value,
      soft_norms: $("soft-norms").value,
    },
  };
  if ($("alternatives").value) body.options.alternatives = $("alternatives").value;
  return body;
}

/** The request last sent: taking an offered alternative sends it again with that answer. */
let lastRequest = null;

/** The paper's expected utterance while the form still holds one of its cases untouched. */
let expected = null;

async function clarify(event) {
  event.preventDefault();
  const form = $("clarify-form");
  clearInvalid(form);
  $("clarify-error").replaceChildren();
  const button = $("clarify-button");
  let request;
  try {
    request = buildRequest();
  } catch (e) {
    showProblem($("clarify-error"), e, FIELD_CONTROLS)?.focus();
    return;
  }
  await send(request, button);
}

/** Sends a clarify request and shows its decision, or the problem with it. */
async function send(request, button) {
  lastRequest = request;
  button.disabled = true;
  $("decision").replaceChildren(h("p", { class: "hint" }, "Simulating every reading…"));
  try {
    const decision = await call("POST", "/v1/clarify", request);
    showDecision(decision);
    showExchange(request, decision);
  } catch (e) {
    $("decision").replaceChildren(h("p", { class: "hint" }, "No decision."));
    $("readings").replaceChildren();
    $("readings-heading").hidden = true;
    marks = { status: {}, chosen: null };
    draw();
    showExchange(request, e instanceof Problem ? e.problem : String(e));
    showProblem($("clarify-error"), e, FIELD_CONTROLS);
  } finally {
    button.disabled = false;
  }
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
  if (alternative && lastRequest) {
    const again = { ...lastRequest, answer: { choice: "alternative" } };
    $("take-alternative").addEventListener("click", () => send(again, $("take-alternative")));
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
// Norms

let norms = [];

async function refreshNorms() {
  try {
    norms = await call("GET", "/v1/norms");
    renderNorms();
  } catch (e) {
    showProblem($("norm-error"), e, NORM_FIELD_CONTROLS);
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
        h("td", {}, n.context ?? "any"),
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
  const severity = $("norm-severity").value.trim();
  if (severity) norm.severity = Number(severity);
  const note = $("norm-note").value.trim();
  if (note) norm.note = note;
  try {
    const stored = await call("POST", "/v1/norms", norm);
    $("norms-status").textContent = `Added norm ${stored.id}: ${stored.kind} ${stored.action ?? stored.state}.`;
    $("norm-term").value = "";
    $("norm-when").value = "";
    $("norm-note").value = "";
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

async function loadVerbs() {
  try {
    const actions = await call("GET", "/v1/actions");
    $("verbs").replaceChildren(...actions.map((a) => h("option", { value: a.name })));
  } catch {
    $("verbs").replaceChildren(...["get", "pointTo", "destroy", "steal", "put"].map((v) => h("option", { value: v })));
  }
}

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
  // The token is kept in the page only; Enter in its field must not reload it.
  $("token-form").addEventListener("submit", (e) => e.preventDefault());
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
  document.body.dataset.ready = "true";
  health();
  loadVerbs();
  refreshNorms();
}

start();

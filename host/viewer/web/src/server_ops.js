// The editor's routes of the one edit model (docs/modeler-protocol.md): the field table
// (GET /fields), the scene's tree (GET /outline), a node's fields (GET /node), operations
// (POST /op: set, add-primitive, add-light, delete, duplicate, camera-from-view, revert),
// each carrying the user action it belongs to, so that a drag is one undo step.
import { getJson, postEdit } from "./api.js";
import { state } from "./state.js";

let table = [];  // GET /fields: every editable field, in the table's order
let actions = 0;

// A fresh user action: one committed field, one add, one delete.
const newAction = kind => `${kind}-${Date.now().toString(36)}-${++actions}`;

// The panel's notes in the words of the scene's format (/state's format; the outline's
// words are the server's labels): a JSON scene has groups, primitives and templates.
const NOTE_WORDS = {
  xml: { block: "transblock", objects: "objects", placed: "an object of a master" },
  json: { block: "group", objects: "primitives", placed: "a primitive of a template" },
};

// The 12 numbers of a `world` field as three rows of four.
const rowsOf = w => [w.slice(0, 4), w.slice(4, 8), w.slice(8, 12)];

// The panel's groups for a node: its fields (those that apply to it, with their values)
// described by the table, grouped under the table's headings, in the table's order. The
// object-to-world matrix is the gizmo's to edit, not the panel's.
function groupsOf(node) {
  const values = new Map(node.fields.map(f => [f.name, f.value]));
  const groups = [];
  for (const spec of table) {
    if (spec.owner !== node.kind) continue;
    if (!values.has(spec.name) || spec.kind === "matrix") continue;
    let group = groups.find(g => g.title === spec.group);
    if (!group) groups.push(group = { title: spec.group, fields: [] });
    group.fields.push({ ...spec, value: values.get(spec.name) });
  }
  const shared = node.kind === "object" && node.own_block === false;
  const transform = groups.find(g => g.title === "transform");
  const words = NOTE_WORDS[state.format] || NOTE_WORDS.xml;
  if (transform && shared)
    transform.note = `its ${words.block} holds other ${words.objects}: moving it gives it a ${words.block} of its own`;
  if (node.instances > 1) groups.push({ title: "placements", fields: [],
    note: `placed ${node.instances} times (${words.placed}): every placement changes` });
  return groups;
}

function selectionOf(node) {
  const world = node.fields.find(f => f.name === "world");
  return {
    ...node,
    type: node.shape || node.type || node.kind,
    // What it is (its kind's label where its text says nothing: a group, the camera), its place.
    description: `${node.text || node.label}${node.path ? " " + node.path : ""}${node.line ? `, line ${node.line}` : ""}`,
    worlds: world ? [rowsOf(world.value)] : undefined,
    groups: groupsOf(node),
  };
}

export const opsServer = {
  name: "ops",
  async available() {
    const { ok, answer } = await getJson("/fields");
    if (ok) table = answer.fields;
    return ok;
  },
  async outline() {
    const { ok, answer } = await getJson("/outline");
    return ok ? answer.nodes : [];
  },
  async load(id) {
    const { ok, answer } = await getJson(`/node?id=${encodeURIComponent(id)}`);
    return ok ? selectionOf(answer) : null;
  },
  async pick(x, y) {
    const { answer } = await getJson(`/pick?x=${x}&y=${y}`);
    const id = answer.node ?? (answer.object === null || answer.object === undefined ? null : `object-${answer.object}`);
    if (!id) return { error: answer.error };
    // The pick's own facts kept with the node's: the pixel and the point the user clicked.
    const node = await this.load(id);
    return node && { ...node, pixel: answer.pixel, point: answer.point };
  },
  // `action`: the gesture the value belongs to (a colour being picked: one undo step); none:
  // a step of its own.
  commit(selection, field, value, action) {
    return postEdit("/op", { action: action ?? newAction("field"), op: "set", node: selection.node,
                             fields: { [field.name]: value } });
  },
  // A drag's move: where the selection is now (its world matrix, as rows), one action.
  move(selection, rows, action) {
    return postEdit("/op", { action, op: "set", node: selection.node, fields: { world: rows.flat() } });
  },
  revert(selection, action) {
    return postEdit("/op", { op: "revert", action });
  },
  newAction,
  // The toolbar's operations: the request, or null for one this server has not.
  operation(name, selection, view) {
    const target = view ? view.position.map((p, i) => p + view.look[i]) : [0, 0, 0];
    const shape = name.startsWith("add-") ? name.slice(4) : null;
    if (shape === "light") return { op: "add-light", type: "point" };
    if (shape) return { op: "add-primitive", shape, fields: { transform: [{ kind: "translate", v: target }] } };
    if (name === "delete" && selection) return { op: "delete", nodes: [selection.node] };
    if (name === "duplicate" && selection) return { op: "duplicate", nodes: [selection.node] };
    if (name === "camera-to-file") return { op: "camera-from-view" };
    return null;
  },
  async run(request) {
    return postEdit("/op", { action: newAction(request.op), ...request });
  },
  editorOf: answer => answer.editor || answer,
  outlineChanged: answer => Boolean(answer.changed && answer.changed.outline),
};

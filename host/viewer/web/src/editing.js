// The page's side of the scene's edits: what is selected, the outline and the properties
// it shows, the toolbar's operations and the drags of the gizmo and the keyboard, each
// turned into a request to the server's editor; and what the page shows after each.
//
// It speaks the editor's routes as they are (POST /edit of an object's material or its
// transblock's transforms, or a light's fields; GET /pick, /object, /state). The one edit
// model of issue 43 (a field table, a tree of the scene, operations that add, delete and
// duplicate, a drag as one undo step) will replace those requests here alone: the outline,
// the properties panel, the overlay and the keys take what this module gives them.
import { getJson, latestOnly, postJson } from "./api.js";
import { frameSphere } from "./camera.js";
import { highlight, showOutline } from "./outline.js";
import { matrixFromRows, moveOutline, rowsFromMatrix, showSelection as showOverlaySelection } from "./overlay.js";
import { showFields } from "./properties.js";
import { emit, record, state } from "./state.js";
import { composeOps, matrixOp } from "./transforms.js";

const editError = document.getElementById("edit-error");
const selectionLine = document.getElementById("selection");
let lights = [];
const seenObjects = new Map();  // id -> { type, path }: the objects selected so far

// ---- What the server says about the editor: file, modified, undo and redo, editable.
export function showEditorState(answer) {
  document.getElementById("file").textContent = answer.file;
  document.getElementById("file").title = answer.file;
  document.getElementById("modified").textContent = answer.modified ? "(modified)" : "";
  document.getElementById("undo").disabled = !answer.can_undo;
  document.getElementById("redo").disabled = !answer.can_redo;
  if (answer.scene_version !== undefined) record.sceneVersion = answer.scene_version;
  if (answer.lights) lights = answer.lights;
  if (answer.editable === false) {
    state.editable = false;
    editError.textContent = "read-only: this viewer was started with --no-token (editing needs the access token)";
    for (const b of document.querySelectorAll("#toolbar button[data-action], #save-as")) {
      if (!["frame-selection", "reset-view"].includes(b.dataset.action)) b.disabled = true;
    }
  } else if (answer.editable) {
    state.editable = true;
  }
}

// A POST to the editor: its answer, or null after showing why it was refused.
async function post(path, body) {
  const { ok, status, answer } = await postJson(path, body);
  if (!ok) {
    editError.textContent = answer.error;
    record.editErrors.push({ status, error: answer.error });
    return { ok, status, answer };
  }
  editError.textContent = "";
  showEditorState(answer);
  return { ok, status, answer };
}

// ---- The selection: an object (by its id) or a light (by its index).
function objectWorlds(o) {
  return [rowsFromMatrix(composeOps(o.transform))];
}

function selectionGroups(s) {
  if (s.light !== undefined) {
    const l = lights[s.light];
    const fields = [{ name: "color", kind: "color", value: l.color }];
    const uses = { point: ["position", "attenuation"], directional: ["direction"],
                   spot: ["position", "direction", "attenuation", "angle", "penumbra"],
                   area: ["position", "direction", "attenuation", "width", "height"] };
    for (const name of uses[l.type] || [])
      fields.push({ name, kind: Array.isArray(l[name]) ? "vector" : "number", value: l[name] });
    return [{ title: `light ${s.light} (${l.type})`, fields }];
  }
  const m = s.material;
  const material = ["diffuse", "ambient", "specular", "reflective", "transparent", "emissive"]
    .map(name => ({ name, kind: "color", value: m[name] }))
    .concat(["shininess", "ior", "blend"].map(name => ({ name, kind: "number", value: m[name] })));
  const transform = s.transform.map((op, i) => ({
    name: op.kind, label: `${i + 1}. ${op.kind}`, kind: op.v.length === 4 ? "vector4" : op.v.length === 3 ? "vector" : "text",
    value: op.v.length <= 4 ? op.v : op.v.join(" "), index: i,
  }));
  const note = s.block_objects > 1 ? `its transblock holds ${s.block_objects} objects: they move together` : "";
  return [{ title: "material", fields: material }, { title: "transform", fields: transform, note }];
}

async function commitField(field, value) {
  const s = state.selection;
  let body;
  if (s.light !== undefined) body = { light: s.light, [field.name]: value };
  else if (field.index !== undefined) {
    const ops = s.transform.map(op => ({ kind: op.kind, v: [...op.v] }));
    ops[field.index].v = value;
    body = { object: s.object, transform: ops };
  } else body = { object: s.object, material: { [field.name]: value } };
  const { ok, status, answer } = await postJson("/edit", body);
  if (!ok) return { ok, status, error: answer.error };
  editError.textContent = "";
  showEditorState(answer);
  record.edits++;
  if (answer.object) setSelection(answer.object, false);
  return { ok };
}

function describe(s) {
  if (!s) return "click an object in the view or the outline to select it";
  if (s.light !== undefined) return `selected: light ${s.light} (${lights[s.light].type})`;
  return `selected: ${s.type} ${s.path} (object ${s.object}, line ${s.line})`;
}

// Shows `s` as the selection everywhere: the outline, the overlay, the properties.
function setSelection(s, rebuildFields = true) {
  state.selection = s && (s.object !== null || s.light !== undefined) ? s : null;
  if (state.selection && state.selection.object !== undefined) state.selection.worlds = objectWorlds(state.selection);
  record.selected = state.selection;
  const sel = state.selection;
  if (sel && sel.object !== undefined && !seenObjects.has(sel.object)) {
    seenObjects.set(sel.object, { type: sel.type, path: sel.path });
    showOutline(outlineNodes(), selectNode, nodeId(sel));
  }
  selectionLine.textContent = sel ? describe(sel) : (s && s.error) || describe(null);
  highlight(sel ? nodeId(sel) : null);
  showOverlaySelection(sel && sel.object !== undefined ? sel : null);
  if (rebuildFields) showFields(sel ? selectionGroups(sel) : [], commitField, sel ? nodeId(sel) : null);
  emit("selection", sel);
}

const nodeId = s => s.light !== undefined ? `light-${s.light}` : `object-${s.object}`;

export async function selectAtPixel({ x, y }) {
  const { answer } = await getJson(`/pick?x=${x}&y=${y}`);
  setSelection(answer);
}

async function selectNode(node) {
  if (node.light !== undefined) return setSelection({ light: node.light });
  if (node.object !== undefined) {
    const { ok, answer } = await getJson(`/object?id=${node.object}`);
    setSelection(ok ? answer : null);
  }
}

function outlineNodes() {
  const nodes = [{ node: "camera", kind: "camera", text: "the file's camera", depth: 0 }];
  lights.forEach((l, i) => nodes.push({ node: `light-${i}`, kind: "light", text: `${l.type} light ${i}`, depth: 0, light: i }));
  for (const [object, o] of seenObjects)
    nodes.push({ node: `object-${object}`, kind: o.type, text: o.path, depth: 0, object });
  return nodes;
}

// After undo, redo or a reload: the scene as it is now.
export async function refreshScene() {
  const { answer } = await getJson("/state");
  showEditorState(answer);
  const s = state.selection;
  if (s && s.object !== undefined) {
    const { ok, answer: o } = await getJson(`/object?id=${s.object}`);
    setSelection(ok ? o : null);
  } else {
    setSelection(s && s.light < lights.length ? s : null);
  }
  showOutline(outlineNodes(), selectNode, s ? nodeId(s) : null);
}

// ---- Drags: the gizmo's and the keyboard's (G, R, S) moves of the selection.
const sendTransform = latestOnly(async body => {
  const began = performance.now();
  const answer = await post("/edit", body);
  record.dragEdits = (record.dragEdits || 0) + 1;
  record.dragEditMs = (record.dragEditMs || 0) + performance.now() - began;
  return answer;
});
let gestureStart = null;  // the selection's transform ops and world matrix when a drag began

export const gesture = {
  begin() {
    const s = state.selection;
    if (!s || s.object === undefined) return false;
    gestureStart = { object: s.object, ops: s.transform, worlds: objectWorlds(s) };
    return true;
  },
  // `delta`: a world-space Matrix4 from where the selection was to where it is now.
  move(delta) {
    if (!gestureStart) return;
    moveOutline(delta, gestureStart.worlds);
    gestureStart.moved = true;
    record.dragMoves = (record.dragMoves || 0) + 1;
    const moved = delta.clone().multiply(matrixFromRows(gestureStart.worlds[0]));
    return sendTransform({ object: gestureStart.object, transform: [matrixOp(moved)] });
  },
  async end(delta) {
    if (!gestureStart) return;
    await this.move(delta);  // the last move answered before the object is read back
    const object = gestureStart.object;
    gestureStart = null;
    const { ok, answer } = await getJson(`/object?id=${object}`);
    if (ok) setSelection(answer);
    record.edits++;
  },
  async cancel() {
    if (!gestureStart) return;
    const { object, ops, moved } = gestureStart;
    gestureStart = null;
    if (moved) await sendTransform({ object, transform: ops });
    refreshScene();
  },
  active: () => gestureStart !== null,
  start: () => gestureStart,
};

// ---- The toolbar's operations.
async function save(body) {
  let { ok, status, answer } = await post("/save", body);
  if (!ok && status === 409 && answer.exists && window.confirm(`${answer.error}\n\nReplace it?`))
    ({ ok, answer } = await post("/save", { ...body, replace: true }));
  if (!ok) return;
  record.saved = answer.saved;
  document.getElementById("saved").textContent = `saved to ${answer.saved}`;
}

// Frames the selection (F): a sphere about its first placement that holds its unit shape.
export function frameSelection() {
  const s = state.selection;
  if (!s || !s.worlds) return;
  const e = matrixFromRows(s.worlds[0]).elements;
  const longestAxis = Math.max(...[0, 1, 2].map(c => Math.hypot(e[4 * c], e[4 * c + 1], e[4 * c + 2])));
  frameSphere([e[12], e[13], e[14]], 0.5 * Math.sqrt(3) * longestAxis);
}

export const actions = {
  undo: async () => { if ((await post("/undo")).ok) refreshScene(); },
  redo: async () => { if ((await post("/redo")).ok) refreshScene(); },
  save: () => save({}),
  "save-as": () => save({ as: document.getElementById("save-as-name").value }),
  "frame-selection": frameSelection,
};

export function runAction(name) {
  const action = actions[name];
  if (action) return action();
  editError.textContent = `${name}: the editor of this viewer cannot do this yet (it waits for issue 43's edit operations)`;
}

export function initEditing(first) {
  showEditorState(first);
  showOutline(outlineNodes(), selectNode, null);
}

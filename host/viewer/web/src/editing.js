// The page's side of the scene's edits: what is selected, the outline and the properties
// it shows, the toolbar's operations and the drags of the gizmo and the keyboard; each
// turned into a request to the server's editor, and what the page shows after each.
//
// The requests themselves are server_ops.js's, in the one edit model (docs/modeler-protocol.md:
// /fields, /outline, /node, /op), which the server that serves this page always has.
import { frameSphere } from "./camera.js";
import { highlight, showOutline } from "./outline.js";
import { matrixFromRows, moveOutline, rowsFromMatrix, showSelection as showOverlaySelection } from "./overlay.js";
import { showFields } from "./properties.js";
import { opsServer } from "./server_ops.js";
import { emit, record, state } from "./state.js";
import { getJson, postEdit } from "./api.js";

const editError = document.getElementById("edit-error");
const selectionLine = document.getElementById("selection");
const server = opsServer;

// ---- What the server says about the editor: file and its format, modified, undo and redo, editable.
export function showEditorState(editor) {
  document.getElementById("file").textContent = editor.file;
  document.getElementById("file").title = editor.file;
  // "save as" keeps the scene's format unless the name says another (.xml, .json).
  if (editor.format) {
    state.format = editor.format;
    document.getElementById("save-as-name").placeholder = `other.${editor.format}`;
  }
  document.getElementById("modified").textContent = editor.modified ? "(modified)" : "";
  state.modified = record.modified = Boolean(editor.modified);  // recovery.js warns before closing
  document.getElementById("undo").disabled = !editor.can_undo;
  document.getElementById("redo").disabled = !editor.can_redo;
  if (editor.scene_version !== undefined) record.sceneVersion = editor.scene_version;
  if (editor.revision !== undefined) record.revision = editor.revision;
  if (editor.editable === false) {
    state.editable = false;
    editError.textContent = "read-only: this viewer was started with --no-token (editing needs the access token)";
    for (const b of document.querySelectorAll("#toolbar button[data-action], #save-as")) {
      if (!["frame-selection", "reset-view"].includes(b.dataset.action)) b.disabled = true;
    }
  } else if (editor.editable) {
    state.editable = true;
  }
}

// An edit refused as made against an older revision of the scene (another page edited it,
// the file was reloaded): the page shows the scene as it is now, and says so.
function stale(reply) {
  if (!reply || reply.status !== 409 || !reply.answer.stale) return false;
  record.staleEdits++;
  refreshScene().then(() => {
    editError.textContent = "The scene changed (another page's edit, or its file was reloaded): your last edit " +
      "was not made. The page now shows the scene as it is; do it again if you still want it.";
  });
  return true;
}

// An answer from the editor: its state shown, or its refusal; the answer.
function answered(reply) {
  if (!reply) return reply;
  if (stale(reply)) {
    record.editErrors.push({ status: reply.status, error: reply.answer.error });
  } else if (!reply.ok) {
    editError.textContent = reply.answer.error;
    record.editErrors.push({ status: reply.status, error: reply.answer.error });
  } else {
    editError.textContent = "";
    showEditorState(server.editorOf(reply.answer));
  }
  return reply;
}

const post = async (path, body) => answered(await postEdit(path, body));

// ---- The selection: any node of the scene (server_*.js describe it).
async function commitField(field, value, action) {
  const reply = await server.commit(state.selection, field, value, action);
  if (!reply.ok) {
    stale(reply);
    return { ok: false, status: reply.status, error: reply.answer.error };
  }
  answered(reply);
  record.edits++;
  await reload();
  return { ok: true };
}

// Shows `s` as the selection everywhere: the outline, the overlay, the properties.
function setSelection(s) {
  state.selection = s && s.node ? s : null;
  record.selected = state.selection;
  const sel = state.selection;
  selectionLine.textContent = sel ? `selected: ${sel.description}`
                                  : (s && s.error) || "click an object in the view or the outline to select it";
  highlight(sel ? sel.node : null);
  showOverlaySelection(sel && sel.worlds ? sel : null);
  // Shown again for the same node, the panel's rows stay and only their values change.
  showFields(sel ? sel.groups : [], commitField, sel ? sel.node : null);
  emit("selection", sel);
}

async function selectNode(id) {
  setSelection(await server.load(id));
}

export async function selectAtPixel({ x, y }) {
  const picked = await server.pick(x, y);
  setSelection(picked);
}

async function showTree() {
  showOutline(await server.outline(), node => selectNode(node.node), state.selection ? state.selection.node : null);
}

// The selection read again (after an edit, an undo, a reload); gone when its node is.
async function reload() {
  if (state.selection) setSelection(await server.load(state.selection.node));
}

export async function refreshScene() {
  const { answer } = await getJson("/state");
  showEditorState(answer);
  await showTree();
  await reload();
}

// ---- Drags: the gizmo's and the keyboard's (G, R, S) moves of the selection, each one user
// action (one undo step), its moves sent one at a time, the latest waiting.
let drag = null;  // { selection, worlds, action, moved, sending, next }

// Sends the drag's latest place, one request at a time: a move made while one is in flight
// waits, and a later one replaces it. Answers when every move so far is answered.
function sendMove(current, rows) {
  current.next = rows;
  if (!current.sending) current.sending = sendWaitingMoves(current);
  return current.sending;
}

async function sendWaitingMoves(current) {
  while (current.next) {
    const rows = current.next;
    current.next = null;
    const began = performance.now();
    answered(await server.move(current.selection, rows, current.action));
    record.dragEdits = (record.dragEdits || 0) + 1;
    record.dragEditMs = (record.dragEditMs || 0) + performance.now() - began;
  }
  current.sending = null;
}

export const gesture = {
  begin() {
    const s = state.selection;
    if (!s || !s.worlds || !state.editable) return false;
    drag = { selection: s, worlds: s.worlds, action: server.newAction("drag"), moved: false, sending: null, next: null };
    return true;
  },
  // `delta`: a world-space Matrix4 from where the selection was to where it is now.
  move(delta) {
    if (!drag) return null;
    moveOutline(delta, drag.worlds);
    drag.moved = true;
    record.dragMoves = (record.dragMoves || 0) + 1;
    return sendMove(drag, rowsFromMatrix(delta.clone().multiply(matrixFromRows(drag.worlds[0]))));
  },
  async end(delta) {
    if (!drag) return;
    const done = drag;
    this.move(delta);
    await done.sending;  // every move answered before the selection is read back
    drag = null;
    record.edits++;
    await reload();
  },
  async cancel() {
    if (!drag) return;
    const done = drag;
    drag = null;
    await done.sending;
    if (done.moved) answered(await server.revert(done.selection, done.action));
    await reload();
  },
  active: () => drag !== null,
};

// ---- The toolbar's operations.
// A file changed on disk by another program since the scene was read is not replaced
// without asking: overwrite it with this scene, or load it as it is (the unsaved edits go).
async function save(body) {
  let reply = await post("/save", body);
  if (!reply.ok && reply.status === 409 && reply.answer.exists && window.confirm(`${reply.answer.error}\n\nReplace it?`))
    reply = await post("/save", { ...body, replace: true });
  if (!reply.ok && reply.status === 409 && reply.answer.changed_on_disk) {
    if (window.confirm(`${reply.answer.error}\n\nOK: overwrite the file with this scene. Cancel: keep the file.`)) {
      reply = await post("/save", { ...body, overwrite: true });
    } else {
      if (window.confirm("Load the file as it is on disk? This scene's unsaved edits are then lost.")) {
        if ((await post("/reload")).ok) await refreshScene();
      }
      return;
    }
  }
  if (!reply.ok) return;
  record.saved = reply.answer.saved;
  document.getElementById("saved").textContent = `saved to ${reply.answer.saved}`;
}

// Frames the selection (F): a sphere about its first placement that holds its unit shape.
export function frameSelection() {
  const s = state.selection;
  if (!s || !s.worlds) return;
  const e = matrixFromRows(s.worlds[0]).elements;
  const longestAxis = Math.max(...[0, 1, 2].map(c => Math.hypot(e[4 * c], e[4 * c + 1], e[4 * c + 2])));
  frameSphere([e[12], e[13], e[14]], 0.5 * Math.sqrt(3) * longestAxis);
}

async function history(which) {
  const reply = await post(`/${which}`);
  if (reply.ok) await refreshScene();
}

// An operation of the edit model (add, delete, duplicate, the view as the file's camera):
// the outline read again when it changed, and what it added selected.
async function operation(name) {
  const request = server.operation(name, state.selection, state.view);
  if (!request) {
    editError.textContent = name === "delete" || name === "duplicate" ? `${name}: select something first`
      : `${name}: the editor of this viewer cannot do this (it has no edit operations: issue 43)`;
    return null;
  }
  const reply = answered(await server.run(request));
  if (!reply || !reply.ok) return null;
  record.edits++;
  if (name === "camera-to-file") state.fileCamera = { position: state.view.position, look: state.view.look, up: state.view.up };
  if (server.outlineChanged(reply.answer)) await showTree();
  const added = reply.answer.added || [];
  if (added.length) await selectNode(added[0]);
  else if ((reply.answer.removed || []).includes(state.selection?.node)) setSelection(null);
  return reply;
}

export const actions = {
  undo: () => history("undo"),
  redo: () => history("redo"),
  save: () => save({}),
  "save-as": () => save({ as: document.getElementById("save-as-name").value }),
  "frame-selection": frameSelection,
};
for (const name of ["add-cube", "add-sphere", "add-cylinder", "add-cone", "add-torus", "add-light", "delete",
                    "duplicate", "camera-to-file"])
  actions[name] = () => operation(name);

export function runAction(name) {
  const action = actions[name];
  return action ? action() : null;
}

export async function initEditing(first) {
  // The field table, which the properties panel is built from.
  if (!(await opsServer.available())) editError.textContent = "the server did not answer GET /fields: no editing";
  record.editor = server.name;
  showEditorState(first);
  await showTree();
}

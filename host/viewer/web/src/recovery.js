// Unsaved edits are never lost from the page's side: the recovery a stopped viewer of this
// scene left (viewer/recovery.h) is offered in a banner, Restore opening its edits as unsaved
// changes and Discard removing it (GET and POST /recovery, docs/modeler-protocol.md); and a
// tab with unsaved edits asks before it closes.
import { getJson, postJson } from "./api.js";
import { record, state } from "./state.js";

const banner = document.getElementById("recovery");
const text = document.getElementById("recovery-text");
const restoreButton = document.getElementById("recovery-restore");
const discardButton = document.getElementById("recovery-discard");
let offer = null;

function show(newOffer) {
  offer = newOffer || null;
  record.recoveryOffer = offer;
  banner.hidden = !offer;
  if (!offer) return;
  text.textContent = `Unsaved edits of this scene from ${offer.written} were kept when a viewer stopped` +
    (offer.scene_changed ? " (the scene file has changed since)" : "") + `: ${offer.file}`;
  banner.title = `the same as ${offer.command}`;
  restoreButton.disabled = discardButton.disabled = !state.editable;
}

// POST /recovery: the editor's state shown after it, then the next offer (or none).
async function answer(action, refreshScene) {
  if (!offer) return;
  restoreButton.disabled = discardButton.disabled = true;
  const reply = await postJson("/recovery", { action, file: offer.file });
  if (!reply.ok) {
    text.textContent = reply.answer.error;
    restoreButton.disabled = discardButton.disabled = false;
    return;
  }
  if (action === "restore") {
    record.restored = reply.answer.restored;
    await refreshScene();
  }
  const next = await getJson("/recovery");
  show(next.ok ? next.answer.offer : null);
}

// Closing or reloading a tab whose edits are not saved asks first (the browser's own
// question: its text is the browser's).
function warnBeforeClosing(event) {
  if (!state.modified || !state.editable) return;
  event.preventDefault();
  event.returnValue = "";  // browsers that ask only when it is set
}

export async function initRecovery(refreshScene) {
  window.addEventListener("beforeunload", warnBeforeClosing);
  restoreButton.addEventListener("click", () => answer("restore", refreshScene));
  discardButton.addEventListener("click", () => answer("discard", refreshScene));
  const { ok, answer: reply } = await getJson("/recovery");
  show(ok ? reply.offer : null);
}

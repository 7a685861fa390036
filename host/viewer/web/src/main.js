// The studio's page: starts every part once the server has said what the view is.
import { getJson } from "./api.js";
import * as editing from "./editing.js";
import "./explain.js";
import { initInput } from "./input.js";
import { initOverlay, setGizmoMode } from "./overlay.js";
import { initRecovery } from "./recovery.js";
import { initSettings } from "./settings.js";
import { on, record, state } from "./state.js";
import { initView, saveImage, streamFrames } from "./view.js";

const CAMERA_FIELDS = ["position", "look", "up"];
// /state's fields that are not the view's (the rest is sent back with each view change).
const NOT_VIEW = ["error", "scene", "device", "view", "scene_version", "file", "modified", "can_undo", "can_redo",
                  "lights", "editable", "fit_window", "revision", "history"];

function initToolbar() {
  for (const button of document.querySelectorAll("#toolbar button[data-action]"))
    button.addEventListener("click", () => editing.runAction(button.dataset.action));
  document.getElementById("save-as").addEventListener("click", () => editing.runAction("save-as"));
  document.getElementById("save").addEventListener("click", saveImage);
  const modes = document.querySelectorAll("#toolbar button[data-mode]");
  for (const button of modes) {
    button.addEventListener("click", () => {
      setGizmoMode(button.dataset.mode);
      for (const b of modes) b.classList.toggle("on", b === button);
    });
  }
}

// A new scene version that the page's own edits did not make (a reload, another page's
// edit) is shown once it is known not to be one of them: the event may come before the
// answer to the edit that made it, and a drag's edits are shown by the drag itself.
let refreshTimer = null;
function refreshUnlessOwn(version) {
  clearTimeout(refreshTimer);
  refreshTimer = setTimeout(() => {
    if (version > record.sceneVersion && !editing.gesture.active()) editing.refreshScene();
  }, 150);
}

async function start() {
  const { ok, status, answer } = await getJson("/state");
  const statusLine = document.getElementById("status");
  if (!ok) {
    statusLine.textContent = status === 403 ? "this viewer needs its access token: open the URL that ray view printed"
                                            : `error ${status}: ${answer.error}`;
    return;
  }
  document.getElementById("error").textContent = answer.error || "";
  state.view = Object.fromEntries(Object.entries(answer).filter(([key]) => !NOT_VIEW.includes(key)));
  state.fileCamera = Object.fromEntries(CAMERA_FIELDS.map(key => [key, answer[key]]));
  await initSettings(state.view);
  await editing.initEditing(answer);
  await initRecovery(editing.refreshScene);
  initToolbar();
  initOverlay(editing.gesture);
  initInput(editing);
  initView(answer);
  on("scene", scene => {
    document.getElementById("error").textContent = scene.error;
    refreshUnlessOwn(scene.version);
  });
  streamFrames();
}
start();

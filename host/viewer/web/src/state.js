// What the page's modules share: the view as the server has it, the frame being shown, the
// selection; and window.rayViewer, what the browser tests and bench/ read (never written
// by them).
export const state = {
  view: null,        // camera and settings: /state's view part, as last sent
  fileCamera: null,  // the scene file's camera, for "reset view" (Home)
  frame: null,       // the frame event of the frame being shown
  selection: null,   // the selected object's description (pick, /object), or null
  editable: false,   // a viewer started with --no-token changes nothing
  modified: false,   // the scene has edits not saved to its file
  format: "xml",     // the scene file's format, "xml" or "json" (/state's editor part)
};

// The page's own record of what it did, for tests and the drag bench: frames seen, the last
// complete frame and the last at rest, each complete frame's arrival (frameLog), edits.
export const record = window.rayViewer = {
  frames: 0, completeFrame: 0, restFrame: null, frameLog: [],
  lastExplain: null, explainState: "none", explains: 0, explainStates: [],
  selected: null, edits: 0, editErrors: [], saved: null, sceneVersion: 0,
  revision: null, staleEdits: 0,  // the scene's revision as last heard; edits refused as made against an older one
};

// Keeps the frame log to the latest few thousand frames (a long session stays small).
export function logFrame(entry) {
  record.frameLog.push(entry);
  if (record.frameLog.length > 4000) record.frameLog.splice(0, 1000);
}

// Listeners of named page events ("selection", "view", "frame", "scene"): one module tells,
// the others follow, and none needs to know who listens.
const listeners = new Map();
export function on(name, listener) {
  if (!listeners.has(name)) listeners.set(name, []);
  listeners.get(name).push(listener);
}
export function emit(name, value) {
  for (const listener of listeners.get(name) || []) listener(value);
}

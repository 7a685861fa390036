// The page's one way to the server. The viewer's access token is written into the page by
// the server (viewer/request_guard.h): every request carries it in a header that no other
// page can send, the event stream (which takes no headers) in its query. A viewer started
// with --no-token writes none.
import { record } from "./state.js";

export const token = document.querySelector('meta[name="ray-token"]').content;

export function api(path, options = {}) {
  const headers = {};
  if (token) headers.Authorization = `token ${token}`;
  if (options.body !== undefined) headers["Content-Type"] = "application/json";
  return fetch(path, { ...options, headers });
}

// GET path: its JSON, or a JSON error object with the status.
export async function getJson(path) {
  const response = await api(path);
  const answer = await response.json().catch(() => ({ error: `HTTP ${response.status}` }));
  return { ok: response.ok, status: response.status, answer };
}

// POST body as JSON: { ok, status, answer }.
export async function postJson(path, body) {
  const response = await api(path, { method: "POST", body: JSON.stringify(body ?? {}) });
  const answer = await response.json().catch(() => ({ error: `HTTP ${response.status}` }));
  return { ok: response.ok, status: response.status, answer };
}

// POST an edit (/op, /undo, /redo, /save, /reload): one at a time, each carrying the
// scene's revision as the page last heard it (record.revision), so that the server refuses
// one made against a scene that changed since (409, "stale"), rather than apply it to what
// the user did not see. Each answer's revision is the next edit's.
let editChain = Promise.resolve();
export function postEdit(path, body) {
  const sent = editChain.then(async () => {
    const revision = record.revision === null ? {} : { revision: record.revision };
    const reply = await postJson(path, { ...(body ?? {}), ...revision });
    const now = reply.answer.editor?.revision ?? reply.answer.state?.revision;
    if (now !== undefined) record.revision = now;
    return reply;
  });
  editChain = sent.catch(() => {});
  return sent;
}

export function eventStream() {
  return new EventSource(token ? `/events?token=${token}` : "/events");
}

// Sends the latest of a stream of requests (a drag sends one per pointer move), one at a
// time: while one is in flight, only the newest waiting is kept, and it goes when the one
// in flight is answered. The server renders the latest in any case; this keeps the
// browser's few connections free and the server from parsing requests it will not render.
export function latestOnly(send) {
  let inFlight = null, waiting = null;
  const run = async (body) => {
    inFlight = send(body);
    try {
      return await inFlight;
    } finally {
      inFlight = null;
      if (waiting) {
        const next = waiting;
        waiting = null;
        next.resolve(run(next.body));
      }
    }
  };
  return (body) => {
    if (!inFlight) return run(body);
    if (waiting) waiting.resolve(null);  // overtaken: never sent
    return new Promise(resolve => { waiting = { body, resolve }; });
  };
}

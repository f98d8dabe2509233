// The live drag's exact previews, asked for off the page's main thread: a main thread busy
// drawing the mesh (or waiting for a software-rendered frame) does not hold up the next
// request. One request in flight, the newest offset wins (each message replaces the one
// waiting); each answer goes back as it came (raw float32 vertices, or the refusal's words).
// Messages in: {token} once, then {id, req} per pointer move, {cancel: true} at the drop.
// Messages out: {id, req, ok, buffer, finite, moved} or {id, req, ok: false, error, network},
// and {idle: true} when nothing is in flight or waiting.
let token = "", waiting = null, busy = false;

onmessage = (e) => {
  const m = e.data;
  if (m.token !== undefined) { token = m.token; return; }
  if (m.cancel) { waiting = null; if (!busy) postMessage({ idle: true }); return; }
  waiting = m;
  if (!busy) send();
};

function allFinite(a) {
  for (let i = 0; i < a.length; i++) if (!Number.isFinite(a[i])) return false;
  return true;
}

async function send() {
  const { id, req } = waiting;
  waiting = null; busy = true;
  try {
    const r = await fetch("/api/drag", {
      method: "POST", body: JSON.stringify(req),
      headers: { "X-Patternfit-Token": token, "Content-Type": "application/json" } });
    if (r.ok) {
      const buffer = await r.arrayBuffer();
      postMessage({ id, req, ok: true, buffer, finite: allFinite(new Float32Array(buffer)),
                    moved: r.headers.get("X-Moved") || "" }, [buffer]);
    } else {
      const body = r.headers.get("content-type")?.includes("json") ? await r.json() : null;
      postMessage({ id, req, ok: false, error: (body && body.error) || `${r.status} ${r.statusText}` });
    }
  } catch (err) {
    postMessage({ id, req, ok: false, network: true, error: String(err) });
  } finally {
    busy = false;
    if (waiting) send(); else postMessage({ idle: true });
  }
}

// Typed arrays from the server: GET with "Accept: application/octet-stream" answers one
// binary body (studio/payload.py): uint32 LE header length n, n bytes of JSON header, then
// the arrays at 4-byte aligned offsets. A dotted array name ("maps.warp.values") is put
// inside the header's objects.
const TYPED = { float32: Float32Array, int32: Int32Array, uint8: Uint8Array };

export function unpack(buffer) {
  const n = new DataView(buffer).getUint32(0, true);
  const head = JSON.parse(new TextDecoder().decode(new Uint8Array(buffer, 4, n)));
  const base = 4 + n;
  for (const [name, a] of Object.entries(head.arrays)) {
    const T = TYPED[a.dtype];
    const array = new T(buffer, base + a.offset, a.bytes / T.BYTES_PER_ELEMENT);
    const path = name.split(".");
    let place = head;
    for (const key of path.slice(0, -1)) place = place[key] = place[key] || {};
    place[path[path.length - 1]] = array;
  }
  delete head.arrays;
  return head;
}

// GET ``path`` as typed arrays; a refusal throws its message
export async function getArrays(path) {
  const r = await fetch(path, { headers: { Accept: "application/octet-stream" } });
  if (!r.ok) {
    const body = r.headers.get("content-type")?.includes("json") ? await r.json() : null;
    throw new Error((body && body.error) || `${r.status} ${r.statusText}`);
  }
  return unpack(await r.arrayBuffer());
}

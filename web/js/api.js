// The REST API as the viewer uses it: same origin, JSON, the error body's message surfaced.
// The API key lives only in this browser (localStorage) and goes out only with writes.
const KEY_STORE = 'locus.apiKey';

export class ApiError extends Error {
  constructor(status, code, message) {
    super(message);
    this.status = status;
    this.code = code;
  }
}

export function apiKey() {
  try { return localStorage.getItem(KEY_STORE) || ''; } catch { return ''; }
}

export function setApiKey(key) {
  try {
    if (key) localStorage.setItem(KEY_STORE, key); else localStorage.removeItem(KEY_STORE);
  } catch { /* storage disabled: the key lasts for this page only */ }
}

async function request(method, path, body, write) {
  const headers = {};
  if (body !== undefined) headers['Content-Type'] = 'application/json';
  const key = write ? apiKey() : '';
  if (key) headers.Authorization = `Bearer ${key}`;
  const res = await fetch(path, { method, headers, body: body === undefined ? undefined : JSON.stringify(body) });
  const text = await res.text();
  let data = null;
  try { data = text ? JSON.parse(text) : null; } catch { data = null; }
  if (!res.ok) {
    const err = data && data.error ? data.error : { code: 'http_' + res.status, message: `${method} ${path}: ${res.status}` };
    throw new ApiError(res.status, err.code, err.message);
  }
  return data;
}

export const get = (path) => request('GET', path);
// Localize and route are reads on the server (no key), though they are POSTs.
export const postRead = (path, body) => request('POST', path, body, false);
export const postWrite = (path, body) => request('POST', path, body, true);

// Every item of a paged list (limit up to 1000 per page).
export async function listAll(path) {
  const items = [];
  const sep = path.includes('?') ? '&' : '?';
  for (let offset = 0; ; ) {
    const page = await get(`${path}${sep}limit=1000&offset=${offset}`);
    items.push(...page.items);
    offset += page.items.length;
    if (page.items.length === 0 || offset >= page.total) return items;
  }
}

// The floor's plan image placement, or null when the floor has none.
export async function imagePlacement(floorId) {
  try {
    return await get(`/v1/floors/${floorId}/image/placement`);
  } catch (e) {
    if (e.status === 404) return null;
    throw e;
  }
}

export async function planOf(floorId) {
  try {
    return await get(`/v1/floors/${floorId}/plan`);
  } catch (e) {
    if (e.status === 404) return null;
    throw e;
  }
}

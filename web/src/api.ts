// The page's only way to the robot: the documented routes, with the owner's bearer token.

const TOKEN_KEY = "joshua-dashboard-token";
const TOKEN_PARAMETER = "token";

/** Moves a token given in the address (`#token=...` as printed, or `?token=...`) into this tab's storage
 * and out of the address bar, so that it stays out of the history, bookmarks and screenshots. */
export function adoptTokenFromAddress(location: Location = window.location): void {
  const fragment = new URLSearchParams(location.hash.slice(1));
  const query = new URLSearchParams(location.search);
  const token = fragment.get(TOKEN_PARAMETER) ?? query.get(TOKEN_PARAMETER);
  if (token === null) return;
  fragment.delete(TOKEN_PARAMETER);
  query.delete(TOKEN_PARAMETER);
  storeApiToken(token);
  const search = query.toString();
  const hash = fragment.toString();
  history.replaceState(null, "", location.pathname + (search ? `?${search}` : "") + (hash ? `#${hash}` : ""));
}

/** The token of this tab (taken from the address first when it carries one), or null. */
export function apiToken(): string | null {
  adoptTokenFromAddress();
  return sessionStorage.getItem(TOKEN_KEY);
}

export function storeApiToken(token: string): void {
  sessionStorage.setItem(TOKEN_KEY, token.trim());
}

export function authHeaders(): Record<string, string> {
  const token = apiToken();
  return token ? { Authorization: `Bearer ${token}` } : {};
}

export class ApiError extends Error {
  /** `kind`: what the dashboard says went wrong (`conflict`, `not_found`, `unreachable`, ...), when it says. */
  constructor(message: string, readonly status: number, readonly kind?: string) {
    super(message);
  }
}

/** The server refused the request for want of the right token. */
export function isUnauthorized(error: unknown): boolean {
  return error instanceof ApiError && error.status === 401;
}

async function reply<T>(response: Response): Promise<T> {
  const body = await response.json().catch(() => ({}));
  if (!response.ok) {
    throw new ApiError(body.error ?? `${response.status} ${response.statusText}`, response.status, body.kind);
  }
  return body as T;
}

export async function getJson<T>(path: string): Promise<T> {
  return reply<T>(await fetch(path, { headers: authHeaders(), cache: "no-store" }));
}

export async function postJson<T>(path: string, body?: unknown): Promise<T> {
  const headers: Record<string, string> = { ...authHeaders() };
  if (body !== undefined) headers["Content-Type"] = "application/json";
  return reply<T>(await fetch(path, { method: "POST", headers, body: body === undefined ? undefined : JSON.stringify(body) }));
}

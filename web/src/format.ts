// How numbers read on the page.

/** A measured value with up to six significant digits, without trailing zeros ("0.125", "-1.5"). */
export function formatValue(value: number | null | undefined): string {
  if (value === null || value === undefined) return "—";
  return String(Number(value.toPrecision(6)));
}

export function formatRate(hz: number | undefined): string {
  if (hz === undefined) return "—";
  return `${hz.toFixed(hz >= 10 ? 0 : 1)} Hz`;
}

export function formatDuration(seconds: number | null): string {
  if (seconds === null) return "—";
  if (seconds < 60) return `${Math.floor(seconds)} s`;
  if (seconds < 3600) return `${Math.floor(seconds / 60)} min`;
  return `${Math.floor(seconds / 3600)} h ${Math.floor((seconds % 3600) / 60)} min`;
}

/** How long ago something happened: tenths of a second below 10 s ("2.5 s"), then as formatDuration. */
export function formatAge(seconds: number): string {
  return seconds < 10 ? `${seconds.toFixed(1)} s` : formatDuration(seconds);
}

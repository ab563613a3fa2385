import react from "@vitejs/plugin-react";
import { fileURLToPath } from "node:url";
import { defineConfig } from "vitest/config";

// Two pages: index.html (one robot, served by the dashboard) and fleet.html (served by joshua-fleet).
export default defineConfig({
  plugins: [react()],
  build: {
    outDir: "dist",
    emptyOutDir: true,
    rollupOptions: { input: { index: "index.html", fleet: "fleet.html" } },
  },
  // The repository, as for a workspace: the tests also read its documents (src/test/docs.test.ts).
  server: { fs: { allow: [fileURLToPath(new URL("..", import.meta.url))] } },
  test: { environment: "jsdom", include: ["src/**/*.test.{ts,tsx}"], globals: true },
});

import react from "@vitejs/plugin-react";
import { defineConfig } from "vitest/config";

// Two pages: index.html (one robot, served by the dashboard) and fleet.html (served by joshua-fleet).
export default defineConfig({
  plugins: [react()],
  build: {
    outDir: "dist",
    emptyOutDir: true,
    rollupOptions: { input: { index: "index.html", fleet: "fleet.html" } },
  },
  test: { environment: "jsdom", include: ["src/**/*.test.{ts,tsx}"], globals: true },
});

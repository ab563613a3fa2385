/** @type {import('tailwindcss').Config} */
export default {
  content: ["./index.html", "./fleet.html", "./src/**/*.{ts,tsx}"],
  theme: { extend: {} },
  plugins: [],
};

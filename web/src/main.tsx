import { StrictMode } from "react";
import { createRoot } from "react-dom/client";
import { App } from "./components/App";
import { EventHubProvider } from "./hooks/EventHubContext";
import "./index.css";

createRoot(document.getElementById("root")!).render(
  <StrictMode>
    <EventHubProvider><App /></EventHubProvider>
  </StrictMode>,
);

import { render, screen } from "@testing-library/react";
import { describe, expect, it } from "vitest";
import { RobotList } from "../fleet/RobotList";
import { FleetAnswerError, httpLink, readRobots } from "../fleet/robots";

const good = { name: "arm", nodes: [{ name: "leader", state: "running" }], last_seen_s: 0.5, online: true,
               url: "http://arm.example:8640/", error: null };

describe("httpLink", () => {
  it("keeps http and https addresses with a host, and nothing else", () => {
    expect(httpLink("http://arm.example:8640/")).toBe("http://arm.example:8640/");
    expect(httpLink("https://10.0.0.5/")).toBe("https://10.0.0.5/");
    for (const url of ["javascript:alert(1)", "JavaScript:alert(1)", " javascript:alert(1)", "java\tscript:alert(1)",
                       "data:text/html,x", "//evil.example/", "/relative", "http://", "file:///etc/passwd", 5, null]) {
      expect(httpLink(url)).toBeNull();
    }
  });
});

describe("readRobots", () => {
  it("keeps the entries of the documented shape, each name once", () => {
    const robots = readRobots([
      good,
      { ...good, name: "evil", url: "javascript:alert(1)" },
      { ...good, name: "broken", nodes: "abc" },
      { ...good, name: "half", nodes: [{ name: "n" }] },
      [1, 2, 3],
      null,
      { ...good, nodes: [] },
    ]);
    expect(robots.map((robot) => [robot.name, robot.url])).toEqual([["arm", "http://arm.example:8640/"], ["evil", null]]);
  });

  it("refuses an answer that is not a list", () => {
    expect(() => readRobots({ robots: [] })).toThrow(FleetAnswerError);
  });
});

describe("RobotList", () => {
  it("links only to http(s) pages and tells an offline robot", () => {
    const [arm, evil] = readRobots([good, { ...good, name: "evil", online: false, last_seen_s: 75,
                                            url: "javascript:alert(1)" }]);
    render(<RobotList robots={[arm, evil]} />);
    expect(screen.getAllByRole("link").map((link) => link.getAttribute("href"))).toEqual(["http://arm.example:8640/"]);
    expect(screen.getByText("offline, last seen 1 min ago")).toBeTruthy();
  });

  it("offers no link to the page of an offline robot, and says why", () => {
    const [offline] = readRobots([{ ...good, online: false, last_seen_s: 12 }]);
    render(<RobotList robots={[offline]} />);
    expect(screen.queryAllByRole("link")).toEqual([]);
    expect(screen.getByTestId("dashboard-offline-arm").textContent).toBe("Dashboard not reachable");
  });
});

describe("releases and rollouts", () => {
  const running = { ...good, nodes: [{ name: "leader", state: "running", ready: true },
                                     { name: "follower", state: "running", ready: false }],
                    release: { build: "3a7d1c09b2e4", built: "2026-01-01T08:59:00.250+09:00" },
                    health: { ready: 1, of: 2 },
                    rollout: [{ name: "arm", release: "3a7d1c09b2e4", state: "updated", step: "", message: "ready",
                                rolled_back_to: "", seconds: 12.34 }] };

  it("keeps a robot's release, health and rollout, and a robot of the rollout not heard from", () => {
    const [arm, quiet] = readRobots([
      running,
      { name: "quiet", nodes: [], last_seen_s: null, online: true, url: null, error: null, release: null, health: null,
        rollout: [{ name: "quiet", release: "b".repeat(12), state: "failed", step: "verify", seconds: null,
                    message: "nodes/leader.py differs from the release's .joshuac-stamp (signed)", rolled_back_to: "" },
                  { name: 7 }] },
    ]);
    expect(arm.release).toEqual({ build: "3a7d1c09b2e4", built: "2026-01-01T08:59:00.250+09:00" });
    expect(arm.health).toEqual({ ready: 1, of: 2 });
    expect(arm.nodes.map((node) => node.ready)).toEqual([true, false]);
    expect(quiet.online).toBe(false);
    expect(quiet.rollout.map((entry) => entry.step)).toEqual(["verify"]);
    expect(readRobots([{ ...running, release: { build: "<img src=x>" } }])[0].release).toBeNull();
  });

  it("shows each robot's release, health and what the rollout did to it", () => {
    const robots = readRobots([
      running,
      { ...running, name: "split", health: { ready: 2, of: 2 },
        rollout: [{ name: "split.arm", state: "failed", step: "gate", message: "node crash failed",
                    rolled_back_to: "c".repeat(12), release: "d".repeat(12), seconds: 30 },
                  { name: "split.pi", state: "not_started", message: "the rollout stopped: canary split.arm failed" }] },
    ]);
    render(<RobotList robots={robots} />);
    expect(screen.getByTestId("release-arm").textContent).toBe("release 3a7d1c09b2e4, built 2026-01-01 08:59:00");
    expect(screen.getByTestId("health-arm").textContent).toBe("ready: 1 of 2 nodes");
    expect(screen.getByTestId("rollout-arm").textContent).toBe("release 3a7d1c09b2e4 rolled out in 12.3 s");
    expect(screen.getByTestId("rollout-split").textContent).toBe(
      `arm: failed at gate: node crash failed; back on ${"c".repeat(12)}` +
      "pi: not started: the rollout stopped: canary split.arm failed");
  });
});

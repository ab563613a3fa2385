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
});

// The Mermaid pictures of README.md, CONTRIBUTING.md and docs/*.md parse, with the parser GitHub renders them with.
import mermaid from "mermaid";

const documents = import.meta.glob(["../../../README.md", "../../../CONTRIBUTING.md", "../../../docs/*.md"], {
  query: "?raw", import: "default", eager: true,
}) as Record<string, string>;

/** The text of every ```mermaid block of a document. */
function mermaidBlocks(text: string): string[] {
  return [...text.matchAll(/^```mermaid\n([\s\S]*?)^```$/gm)].map((match) => match[1]);
}

describe("the documents' Mermaid pictures", () => {
  it("include the architecture's", () => {
    const architecture = Object.entries(documents).find(([path]) => path.endsWith("/docs/architecture.md"));
    expect(architecture).toBeDefined();
    expect(mermaidBlocks(architecture![1]).length).toBeGreaterThanOrEqual(2);
  });

  for (const [path, text] of Object.entries(documents)) {
    mermaidBlocks(text).forEach((block, index) => {
      it(`parse: ${path.replace(/^(\.\.\/)+/, "")}, picture ${index + 1}`, async () => {
        await expect(mermaid.parse(block)).resolves.toMatchObject({ diagramType: expect.any(String) });
      });
    });
  }

  it("refuse a picture that is not well formed", async () => {
    await expect(mermaid.parse("flowchart LR\n  a[\"A\"] --> b[\"B\"\n")).rejects.toThrow(/Parse error/);
  });
});

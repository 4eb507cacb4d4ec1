import { describe, expect, it } from "vitest";
import { resolveTheme } from "./theme";

describe("the colour theme", () => {
  it("follows the system unless the operator chose one", () => {
    expect(resolveTheme("system", true)).toBe("light");
    expect(resolveTheme("system", false)).toBe("dark");
    expect(resolveTheme("light", false)).toBe("light");
    expect(resolveTheme("dark", true)).toBe("dark");
  });
});

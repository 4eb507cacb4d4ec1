import { startLauncher, startStack } from "./stack";

export default async function globalSetup(): Promise<void> {
  await startLauncher();
  const stack = await startStack();
  process.env.SEM_E2E_URL = stack.url;
}

import { stopLauncher, stopStack } from "./stack";

export default async function globalTeardown(): Promise<void> {
  await stopStack();
  await stopLauncher();
}

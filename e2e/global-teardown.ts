import { stopLauncher, stopStack } from "./stack";

export default async function globalTeardown(): Promise<void> {
  try {
    await stopStack();
  } finally {
    await stopLauncher();
  }
}

// The one way the browser tests start Chromium: Debian's (or $CHROMIUM), headless, with nothing
// of its own on the network (no QUIC, updates, sync or background fetches), so that a test sees
// only the requests its page makes.

import { chromium } from "playwright-core";

export function launch() {
  return chromium.launch({
    executablePath: process.env.CHROMIUM ?? "/usr/bin/chromium",
    args: [
      "--headless",
      "--no-sandbox",
      "--disable-gpu",
      "--disable-quic",
      "--no-first-run",
      "--disable-background-networking",
      "--disable-component-update",
      "--disable-sync",
    ],
  });
}

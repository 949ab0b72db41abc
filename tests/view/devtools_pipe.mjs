// Headless Chromium driven over its DevTools debugging pipe (fd 3 in, fd 4 out,
// NUL-separated JSON), which needs no WebSocket client: shared by the view's browser test
// and the page frame-rate bench.

/// The flags the view's browser checks run Chromium with (a new profile in `profile`).
export function chromiumArguments(profile) {
  return ['--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
    '--disable-background-networking', '--disable-component-update', '--disable-sync',
    // WebGL on the CPU (SwiftShader) without a GPU.
    '--enable-unsafe-swiftshader',
    `--user-data-dir=${profile}`, '--window-size=900,700', '--remote-debugging-pipe', 'about:blank'];
}

/// Commands to, and events from, a Chromium spawned with stdio[3] and stdio[4] as pipes.
export class DevTools {
  constructor(browser) {
    this.input = browser.stdio[3];
    this.next = 1;
    this.waiting = new Map();
    this.listeners = [];
    let pending = '';
    browser.stdio[4].on('data', (chunk) => {
      pending += chunk.toString('utf8');
      let end;
      while ((end = pending.indexOf('\0')) >= 0) {
        const message = JSON.parse(pending.slice(0, end));
        pending = pending.slice(end + 1);
        if (message.id && this.waiting.has(message.id)) {
          const { resolve, reject } = this.waiting.get(message.id);
          this.waiting.delete(message.id);
          if (message.error) reject(new Error(JSON.stringify(message.error))); else resolve(message.result);
        } else if (message.method) for (const listener of this.listeners) listener(message);
      }
    });
  }

  send(method, params = {}, sessionId = undefined) {
    const id = this.next++;
    this.input.write(JSON.stringify({ id, method, params, sessionId }) + '\0');
    return new Promise((resolve, reject) => this.waiting.set(id, { resolve, reject }));
  }

  /// Opens `url` in a new page; returns a function sending commands to that page.
  async openPage(url) {
    const { targetId } = await this.send('Target.createTarget', { url: 'about:blank' });
    const { sessionId } = await this.send('Target.attachToTarget', { targetId, flatten: true });
    const page = (method, params) => this.send(method, params, sessionId);
    page.sessionId = sessionId;
    await page('Emulation.setDeviceMetricsOverride', { width: 900, height: 700, deviceScaleFactor: 1, mobile: false });
    return page;
  }
}

/// The value of `expression` in the page (awaited, by value).
export async function evaluate(page, expression) {
  const { result, exceptionDetails } = await page('Runtime.evaluate', { expression, returnByValue: true, awaitPromise: true });
  if (exceptionDetails) throw new Error(`${expression}: ${exceptionDetails.text}`);
  return result.value;
}

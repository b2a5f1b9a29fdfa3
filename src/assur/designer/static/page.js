// The standalone page of `assur design`: an anywidget-like model over the server's WebSocket, then the designer.
//
// The server's messages are JSON text frames; a message with `"binary": true` is followed by one binary frame
// (its float64 arrays), and both are delivered together to the "msg:custom" handlers, as a widget would.
// A share fragment (#m=...) is read by the designer itself once the first result has arrived. index.html loads
// plotly (the 3D view) deferred, after this module.
import designer, { preferReadbackCanvases } from "./designer.js";

// before plotly (loaded after this module) creates its text canvases: see preferReadbackCanvases
preferReadbackCanvases();

function socketUrl(token) {
  const scheme = location.protocol === "https:" ? "wss" : "ws";
  return `${scheme}://${location.host}/ws?token=${encodeURIComponent(token)}`;
}

function createSocketModel(token) {
  const handlers = new Set();
  const outbox = [];
  let waitingForBuffer = null; // the text half of a binary message
  const socket = new WebSocket(socketUrl(token));
  socket.binaryType = "arraybuffer";

  const deliver = (message, buffers) => {
    for (const handler of handlers) handler(message, buffers);
  };
  socket.addEventListener("open", () => {
    for (const text of outbox.splice(0)) socket.send(text);
  });
  socket.addEventListener("message", (event) => {
    if (typeof event.data === "string") {
      const message = JSON.parse(event.data);
      if (message.binary) waitingForBuffer = message;
      else deliver(message, []);
      return;
    }
    const message = waitingForBuffer;
    waitingForBuffer = null;
    if (message) deliver(message, [new DataView(event.data)]);
  });
  socket.addEventListener("close", () => deliver({ type: "connection", state: "closed" }, []));

  return {
    send(content) {
      const text = JSON.stringify(content);
      if (socket.readyState === WebSocket.OPEN) socket.send(text);
      else outbox.push(text);
    },
    on(event, handler) {
      if (event === "msg:custom") handlers.add(handler);
    },
    off(event, handler) {
      if (event === "msg:custom") handlers.delete(handler);
    },
    get(name) {
      return name === "token" ? token : undefined;
    },
  };
}

const token = new URLSearchParams(location.search).get("token") || "";
designer.render({ model: createSocketModel(token), el: document.getElementById("app") });

// A second, independent rosbridge v2 client (roslibjs in Node) for conformance tests of the
// simulated chair. tests/test_sim_roslibjs.py runs it; it prints ONE JSON line with what it saw.
//
// Usage: node roslib_client.mjs --url ws://127.0.0.1:PORT [--flavour ros1|ros2] [--seconds 1.5]
//                               [--missing-map /no/such/map.yaml] [--timeout 5]
// Options may also come as one JSON object on stdin when --stdin is given.
//
// Everything is bounded: each step has a timeout, the whole run has a hard deadline, and the
// process exits by itself. Exit code 0 = the run completed (checks are the caller's job),
// 2 = could not connect, 3 = hard deadline hit (the JSON line is printed in every case).
import * as ROSLIB from "roslib";

function parseArgs(argv) {
  const opts = { flavour: "ros1", seconds: 1.5, missingMap: "/nonexistent/pmk/missing.yaml", timeout: 5 };
  for (let i = 0; i < argv.length; i++) {
    const key = argv[i];
    const val = argv[i + 1];
    if (key === "--url") opts.url = val;
    else if (key === "--flavour") opts.flavour = val;
    else if (key === "--seconds") opts.seconds = Number(val);
    else if (key === "--missing-map") opts.missingMap = val;
    else if (key === "--timeout") opts.timeout = Number(val);
    else if (key === "--stdin") { opts.stdin = true; continue; }
    else throw new Error(`unknown argument ${key}`);
    i++;
  }
  return opts;
}

async function readStdinJson() {
  const chunks = [];
  for await (const chunk of process.stdin) chunks.push(chunk);
  const text = Buffer.concat(chunks).toString("utf8").trim();
  return text ? JSON.parse(text) : {};
}

const sleep = (ms) => new Promise((r) => setTimeout(r, ms));

/** Resolve {ok, value | error, ms} from a roslibjs callback-style call; never rejects. */
function callback(fn, timeoutS) {
  const t0 = performance.now();
  return new Promise((resolve) => {
    const timer = setTimeout(() => resolve({ ok: false, error: `timeout after ${timeoutS} s`, timedOut: true }), timeoutS * 1000);
    const done = (ok) => (x) => {
      clearTimeout(timer);
      const ms = Math.round(performance.now() - t0);
      resolve(ok ? { ok: true, value: x, ms } : { ok: false, error: x, ms });
    };
    try {
      fn(done(true), done(false));
    } catch (err) {
      done(false)(`threw ${err}`);
    }
  });
}

/** Wrap roslibjs' own transport factory to log the ops we send and the status ops we receive. */
function recordingFactory(log) {
  return async (url) => {
    const transport = await ROSLIB.WebSocketTransportFactory(url);
    const send = transport.send.bind(transport);
    transport.send = (msg) => {
      log.sent.push({ op: msg.op, topic: msg.topic, service: msg.service, type: msg.type });
      send(msg);
    };
    transport.on("message", (msg) => {
      log.received[msg.op] = (log.received[msg.op] ?? 0) + 1;
      if (msg.op === "status") log.status.push({ level: msg.level, msg: msg.msg, id: msg.id });
    });
    transport.on("error", (err) => log.errors.push(String(err?.message ?? err)));
    return transport;
  };
}

function connect(url, log, timeoutS) {
  const ros = new ROSLIB.Ros({ transportFactory: recordingFactory(log) });
  ros.on("error", (err) => log.errors.push(String(err?.message ?? err)));
  return new Promise((resolve) => {
    const timer = setTimeout(() => resolve({ ros, ok: false, error: `no connection within ${timeoutS} s` }), timeoutS * 1000);
    ros.on("connection", () => { clearTimeout(timer); resolve({ ros, ok: true }); });
    ros.on("close", () => { log.closed = true; });
    ros.connect(url).catch((err) => { clearTimeout(timer); resolve({ ros, ok: false, error: String(err) }); });
  });
}

const stampKeys = (header) => (header && header.stamp ? Object.keys(header.stamp).sort() : null);

function rateOf(times) {
  if (times.length < 2) return 0;
  return (times.length - 1) / ((times[times.length - 1] - times[0]) / 1000);
}

async function main() {
  let opts = parseArgs(process.argv.slice(2));
  if (opts.stdin) opts = { ...opts, ...(await readStdinJson()) };
  if (!opts.url) throw new Error("--url is required");
  const ros2 = opts.flavour === "ros2";
  const msgType = (pkg, name) => (ros2 ? `${pkg}/msg/${name}` : `${pkg}/${name}`);
  const srvType = (pkg, name) => (ros2 ? `${pkg}/srv/${name}` : `${pkg}/${name}`);
  const out = { roslib: ROSLIB.REVISION ?? null, node: process.version, flavour: opts.flavour };
  const log = { sent: [], received: {}, status: [], errors: [], closed: false };
  out.log = log;

  const hard = setTimeout(() => {
    out.fatal = "hard deadline hit";
    console.log(JSON.stringify(out));
    process.exit(3);
  }, (opts.seconds + 6 * opts.timeout) * 1000);

  const conn = await connect(opts.url, log, opts.timeout);
  out.connected = conn.ok;
  if (!conn.ok) {
    out.fatal = conn.error;
    console.log(JSON.stringify(out));
    clearTimeout(hard);
    process.exit(2);
  }
  const ros = conn.ros;

  // --- topics on the 1st socket: /odom, /scan, latched /map; the 2nd socket adds png, cbor and relative names
  const odom = { count: 0, times: [], first: null, maxVx: 0 };
  const scan = { count: 0, first: null };
  const map = { count: 0, first: null, ms: null };
  const t0 = performance.now();
  const odomTopic = ros.Topic({ name: "/odom", messageType: msgType("nav_msgs", "Odometry") });
  odomTopic.subscribe((m) => {
    odom.count++;
    odom.times.push(performance.now());
    odom.first ??= m;
    odom.maxVx = Math.max(odom.maxVx, m?.twist?.twist?.linear?.x ?? 0);
  });
  const scanTopic = ros.Topic({ name: "/scan", messageType: msgType("sensor_msgs", "LaserScan") });
  scanTopic.subscribe((m) => { scan.count++; scan.first ??= m; });
  const mapTopic = ros.Topic({ name: "/map", messageType: msgType("nav_msgs", "OccupancyGrid") });
  mapTopic.subscribe((m) => { map.count++; if (!map.first) { map.first = m; map.ms = Math.round(performance.now() - t0); } });

  const secondLog = { sent: [], received: {}, status: [], errors: [], closed: false };
  const second = await connect(opts.url, secondLog, opts.timeout);
  const pngMap = { count: 0, first: null };
  const cborOdom = { count: 0, first: null };
  const relOdom = { count: 0 };
  if (second.ok) {
    const t = second.ros.Topic({ name: "/map", messageType: msgType("nav_msgs", "OccupancyGrid"), compression: "png" });
    t.subscribe((m) => { pngMap.count++; pngMap.first ??= m; });
    // rosbridge answers 'cbor' with binary CBOR frames; a server without CBOR must fall back to JSON
    const c = second.ros.Topic({ name: "/odom", messageType: msgType("nav_msgs", "Odometry"), compression: "cbor" });
    c.subscribe((m) => { cborOdom.count++; cborOdom.first ??= m; });
    // a relative topic name: rosbridge resolves it in its namespace ('odom' -> '/odom') and keeps
    // the client's spelling in the publish ops it sends back (roslibjs routes messages by that string)
    const r = second.ros.Topic({ name: "odom", messageType: msgType("nav_msgs", "Odometry") });
    r.subscribe(() => { relOdom.count++; });
  }

  // --- publish /cmd_vel at 10 Hz during the window; the chair should start moving
  const cmdVel = ros.Topic({ name: "/cmd_vel", messageType: msgType("geometry_msgs", "Twist") });
  const twist = { linear: { x: 0.2, y: 0, z: 0 }, angular: { x: 0, y: 0, z: 0.1 } };
  let published = 0;
  const pubTimer = setInterval(() => { cmdVel.publish(twist); published++; }, 100);

  // --- services, concurrently with the topic window
  const T = opts.timeout;
  const service = (name, type, args) =>
    callback((ok, fail) => ros.Service({ name, serviceType: type }).callService(args, ok, fail), T);
  const reloadName = ros2 ? "/map_server/load_map" : "/change_map";
  const reloadType = ros2 ? srvType("nav2_msgs", "LoadMap") : srvType("nav_msgs", "LoadMap");
  const calls = Promise.all([
    service("/rosapi/topics", srvType(ros2 ? "rosapi_msgs" : "rosapi", "Topics"), {}),
    service(reloadName, reloadType, { map_url: opts.missingMap }),
    service(reloadName, reloadType, { map_url: "" }),
    service("/no_such_service", srvType("std_srvs", "Trigger"), {}),
    callback((ok, fail) => ros.getTopics(ok, fail), T),
    callback((ok, fail) => ros.getServices(ok, fail), T),
    callback((ok, fail) => ros.getTopicType("/odom", ok, fail), T),
    callback((ok, fail) => ros.getTopicType("/no_such_topic", ok, fail), T),
    callback((ok, fail) => ros.getTopicsForType(msgType("nav_msgs", "Odometry"), ok, fail), T),
    callback((ok, fail) => ros.getServiceType(reloadName, ok, fail), T),
  ]);
  // --- a service provided BY a client (2nd socket) and called by another (1st socket) through the bridge
  const provided = (async () => {
    if (!second.ok) return { error: second.error };
    const name = "/pmk_test/set_flag";
    const type = srvType("std_srvs", "SetBool");
    const server = second.ros.Service({ name, serviceType: type });
    const seen = [];
    await server.advertiseAsync(async (req) => {
      seen.push(req);
      if (!req.data) throw new Error("refused by provider");
      return { success: true, message: "flag on" };
    });
    await sleep(200); // the advertise travelled on the other socket
    const on = await service(name, type, { data: true });
    const off = await service(name, type, { data: false });
    await server.unadvertise();
    await sleep(200);
    const gone = await service(name, type, { data: true });
    return { on, off, gone, seen };
  })();
  await sleep(opts.seconds * 1000);
  clearInterval(pubTimer);
  cmdVel.publish({ linear: { x: 0, y: 0, z: 0 }, angular: { x: 0, y: 0, z: 0 } });
  const [rosapiTopics, reload, reloadEmpty, unknown, getTopics, getServices, topicType, topicTypeUnknown, topicsForType, serviceType] =
    await calls;
  out.provided = await provided;

  // --- unsubscribe, then make sure /odom really stops (rosbridge stops sending after unsubscribe)
  odomTopic.unsubscribe();
  scanTopic.unsubscribe();
  mapTopic.unsubscribe();
  cmdVel.unadvertise();
  await sleep(150); // messages already in flight when unsubscribe was sent
  const odomAfterUnsub = odom.count;
  await sleep(300);

  const header = odom.first?.header;
  out.odom = {
    count: odom.count,
    rate: rateOf(odom.times),
    stampKeys: stampKeys(header),
    headerKeys: header ? Object.keys(header).sort() : null,
    frameId: header?.frame_id ?? null,
    childFrameId: odom.first?.child_frame_id ?? null,
    stamp: header?.stamp ?? null,
    maxVx: odom.maxVx,
    extraAfterUnsubscribe: odom.count - odomAfterUnsub,
  };
  out.scan = {
    count: scan.count,
    ranges: scan.first?.ranges?.length ?? null,
    angleMin: scan.first?.angle_min ?? null,
    angleMax: scan.first?.angle_max ?? null,
    angleIncrement: scan.first?.angle_increment ?? null,
    stampKeys: stampKeys(scan.first?.header),
    frameId: scan.first?.header?.frame_id ?? null,
  };
  const mapSummary = (m) =>
    m.first && {
      count: m.count,
      width: m.first.info?.width,
      height: m.first.info?.height,
      resolution: m.first.info?.resolution,
      dataLength: m.first.data?.length,
      stampKeys: stampKeys(m.first.header),
      frameId: m.first.header?.frame_id,
    };
  out.map = map.first ? { ...mapSummary(map), firstMs: map.ms } : { count: 0 };
  out.mapPng = second.ok ? (pngMap.first ? mapSummary(pngMap) : { count: 0 }) : { error: second.error };
  out.odomRelative = { count: relOdom.count };
  out.odomCbor = { count: cborOdom.count, x: cborOdom.first?.pose?.pose?.position?.x ?? null };
  out.secondLog = { received: secondLog.received, status: secondLog.status, errors: secondLog.errors };
  out.cmdVel = { published };
  out.calls = {
    rosapiTopics,
    reload: { service: reloadName, ...reload },
    reloadEmpty,
    unknown,
    getTopics,
    getServices,
    topicType,
    topicTypeUnknown,
    topicsForType,
    serviceType,
  };

  ros.close();
  if (second.ok) second.ros.close();
  // the close handshake needs the server's reply: wait for the "close" events (bounded), not a
  // fixed 100 ms that a loaded machine overruns (log.closed false although the close was clean)
  for (let i = 0; i < 100 && !(log.closed && (!second.ok || secondLog.closed)); i++) await sleep(50);
  clearTimeout(hard);
  console.log(JSON.stringify(out));
  process.exit(0);
}

main().catch((err) => {
  console.log(JSON.stringify({ fatal: String(err?.stack ?? err) }));
  process.exit(1);
});

// Paints the scene of draw.js on the canvas handed over, and again on each message.
importScripts('draw.js'); let ctx, n = 0;
onmessage = (e) => { if (e.data.canvas) ctx = e.data.canvas.getContext('2d'); paint(ctx, scene(++n)); };

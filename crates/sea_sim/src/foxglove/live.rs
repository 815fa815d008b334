//! Live view: the channels of a run served over the Foxglove WebSocket protocol.

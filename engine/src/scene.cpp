// scene: being written.

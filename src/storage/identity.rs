//! Whether a database path still names the file the store opened, asked before every request.
//! On Linux the kernel says when anything along the path changed (inotify): a request then costs
//! one `poll` of that queue, and a `stat` of the path only after a change that may matter.
//! Elsewhere, or when the kernel will not watch, every request costs the `stat`.
//!
//! Must not: answer "the same file" to a request that starts after the file was deleted or
//! replaced. The kernel queues a change's event before the call that made it returns, so a
//! later request finds the event queued, or a check under way (see `Watch::check`). What no
//! watched event reports (a file system mounted over a directory of the path; a link in a third
//! directory that a link on the path leads through, turned) is seen by the `stat` that writes
//! and each lease's read of the versions make, within one lease.

use std::path::{Path, PathBuf};

use super::StoreError;

/// The file a store opened, by the path it was opened at.
#[derive(Debug)]
pub struct FileIdentity {
    path: PathBuf,
    /// (device, inode) of the file when opened.
    opened: (u64, u64),
    #[cfg(target_os = "linux")]
    watch: Option<watch::Watch>,
}

fn identity(path: &Path) -> std::io::Result<(u64, u64)> {
    use std::os::unix::fs::MetadataExt;
    let metadata = std::fs::metadata(path)?;
    Ok((metadata.dev(), metadata.ino()))
}

impl FileIdentity {
    /// The file `path` names now, and a watch on the path when the kernel grants one.
    pub fn of(path: &Path) -> std::io::Result<FileIdentity> {
        // Watched before the file is identified: a change in between is queued, and the first
        // check stats anyway.
        #[cfg(target_os = "linux")]
        let watch = watch::Watch::new(path);
        Ok(FileIdentity {
            path: path.to_owned(),
            opened: identity(path)?,
            #[cfg(target_os = "linux")]
            watch,
        })
    }

    /// Whether the path still names the file opened; the error says how it does not.
    pub fn check(&self) -> Result<(), StoreError> {
        #[cfg(target_os = "linux")]
        if let Some(watch) = &self.watch {
            return watch.check(|| self.stat());
        }
        self.stat()
    }

    /// Whether a change along the path is noticed without a `stat` per request.
    #[cfg(test)]
    pub fn watched(&self) -> bool {
        #[cfg(target_os = "linux")]
        return self.watch.as_ref().is_some_and(watch::Watch::sees);
        #[cfg(not(target_os = "linux"))]
        false
    }

    /// The full check: one `stat` of the path.
    pub fn stat(&self) -> Result<(), StoreError> {
        match identity(&self.path) {
            Ok(now) if now == self.opened => Ok(()),
            Ok(_) => Err(StoreError::new(format!(
                "{} was replaced by another file",
                self.path.display()
            ))),
            Err(e) => Err(StoreError::new(format!("{} is gone: {e}", self.path.display()))),
        }
    }
}

#[cfg(target_os = "linux")]
mod watch {
    use std::collections::HashMap;
    use std::ffi::{CString, OsStr, OsString};
    use std::os::fd::{AsRawFd, FromRawFd, OwnedFd};
    use std::os::unix::ffi::OsStrExt;
    use std::path::{Path, PathBuf};
    use std::sync::atomic::{AtomicBool, Ordering};
    use std::sync::{Mutex, PoisonError};

    use super::StoreError;

    /// What a directory on the path is watched for: its own end, and entries made, removed or
    /// renamed in it (a file or directory put in place of one the path goes through).
    const DIRECTORY: u32 = libc::IN_CREATE
        | libc::IN_DELETE
        | libc::IN_MOVED_FROM
        | libc::IN_MOVED_TO
        | libc::IN_MOVE_SELF
        | libc::IN_DELETE_SELF
        | libc::IN_ONLYDIR;
    /// File systems whose every change is made by this kernel, and so reported to its watches,
    /// by `statfs` magic number. On any other (NFS, SMB, FUSE, ...) another host may change the
    /// path unseen, so the path is stat'ed per request.
    const LOCAL: [u64; 9] = [
        0xEF53,      // ext2, ext3, ext4
        0x5846_5342, // XFS
        0x9123_683E, // Btrfs
        0x0102_1994, // tmpfs
        0x794C_7630, // overlayfs
        0x2FC1_2FC1, // ZFS
        0xF2F5_2010, // F2FS
        0x8584_58F6, // ramfs
        0xCA45_1A4E, // bcachefs
    ];
    /// Past this many watches (each path's directories, again after each change that replaced
    /// one), the path is stat'ed per request instead.
    const MAX_WATCHES: usize = 256;

    #[derive(Debug)]
    pub struct Watch {
        /// The inotify queue; non-blocking.
        queue: OwnedFd,
        /// Set from before a check drains the queue until the `stat` after the drain finds the
        /// file the same; left set while it does not. A request trusts an empty queue only
        /// while this is clear.
        doubt: AtomicBool,
        state: Mutex<State>,
        /// The path as given and made absolute (not resolved): its directories' entries are
        /// what the kernel looks up, symbolic links included.
        path: PathBuf,
    }

    #[derive(Debug, Default)]
    struct State {
        /// Each watched directory (by watch descriptor) with the names in it the path goes
        /// through. The file itself needs no watch: deleting it, or renaming anything over it
        /// or it away, is an entry event in its directory.
        directories: HashMap<i32, Vec<OsString>>,
        /// No `stat` since the watches were set has found the file the same, or the last one
        /// found it not the same.
        unconfirmed: bool,
        /// The kernel refused a watch or lost events: every check stats.
        blind: bool,
    }

    impl Watch {
        pub fn new(path: &Path) -> Option<Watch> {
            let path = std::path::absolute(path).ok()?;
            // SAFETY: no pointers; the result is checked.
            let fd = unsafe { libc::inotify_init1(libc::IN_NONBLOCK | libc::IN_CLOEXEC) };
            if fd < 0 {
                tracing::debug!(error = %std::io::Error::last_os_error(), "no inotify queue: the database path is stat'ed per request");
                return None;
            }
            // SAFETY: `fd` was just opened and is owned here alone.
            let queue = unsafe { OwnedFd::from_raw_fd(fd) };
            let watch = Watch {
                queue,
                // The first check stats: a change before the watches were set is seen by it.
                doubt: AtomicBool::new(true),
                state: Mutex::new(State {
                    unconfirmed: true,
                    ..State::default()
                }),
                path,
            };
            let mut state = watch.state.lock().unwrap_or_else(PoisonError::into_inner);
            watch.rewatch(&mut state);
            let blind = state.blind;
            drop(state);
            (!blind).then_some(watch)
        }

        /// Whether changes are still seen without a `stat` per request.
        #[cfg(test)]
        pub fn sees(&self) -> bool {
            !self.state.lock().unwrap_or_else(PoisonError::into_inner).blind
        }

        /// `stat` is the full check. The fast path reads the queue and then `doubt`, in that
        /// order: a check that drained an event set `doubt` first, and clears it only once its
        /// `stat`, made after the drain and so after the change, found the file the same.
        pub fn check(&self, stat: impl FnOnce() -> Result<(), StoreError>) -> Result<(), StoreError> {
            if !self.queued() && !self.doubt.load(Ordering::SeqCst) {
                return Ok(());
            }
            let mut state = self.state.lock().unwrap_or_else(PoisonError::into_inner);
            if state.blind {
                return stat();
            }
            self.doubt.store(true, Ordering::SeqCst);
            let changed = self.drain(&mut state);
            if changed {
                // Before the `stat`: a change racing it lands on a watch already set.
                self.rewatch(&mut state);
            }
            if changed || state.unconfirmed || state.blind {
                let result = stat();
                state.unconfirmed = result.is_err();
                if state.unconfirmed || state.blind {
                    return result;
                }
            }
            self.doubt.store(false, Ordering::SeqCst);
            Ok(())
        }

        /// Whether an event is queued, without taking it.
        fn queued(&self) -> bool {
            let mut poll = libc::pollfd {
                fd: self.queue.as_raw_fd(),
                events: libc::POLLIN,
                revents: 0,
            };
            // SAFETY: one valid pollfd, no wait. On an error the answer is "queued": the
            // check then drains, and an error there makes it blind.
            let ready = unsafe { libc::poll(&mut poll, 1, 0) };
            ready != 0
        }

        /// Takes every queued event; true if one may change what the path names.
        fn drain(&self, state: &mut State) -> bool {
            // inotify events are 4-byte aligned records.
            #[repr(C, align(4))]
            struct Buffer([u8; 4096]);
            let mut buffer = Buffer([0; 4096]);
            let mut changed = false;
            loop {
                // SAFETY: the buffer is valid for its length.
                let read = unsafe { libc::read(self.queue.as_raw_fd(), buffer.0.as_mut_ptr().cast(), buffer.0.len()) };
                // The queue never ends (0 is not read from it); taken as empty if it did.
                if read == 0 {
                    return changed;
                }
                if read < 0 {
                    let error = std::io::Error::last_os_error();
                    if error.kind() != std::io::ErrorKind::WouldBlock {
                        state.blind(&error);
                    }
                    return changed;
                }
                let mut events = &buffer.0[..read as usize];
                while events.len() >= 16 {
                    let word = |at: usize| u32::from_ne_bytes(events[at..at + 4].try_into().expect("4 bytes"));
                    let (wd, mask, len) = (word(0) as i32, word(4), word(12) as usize);
                    let name = events.get(16..16 + len).unwrap_or_default();
                    let name = &name[..name.iter().position(|&b| b == 0).unwrap_or(name.len())];
                    changed |= state.matters(wd, mask, OsStr::from_bytes(name));
                    events = events.get(16 + len..).unwrap_or_default();
                }
            }
        }

        /// Watches every directory the path goes through, as given and as resolved, as they
        /// are now. Parts that do not exist are covered by their parent's
        /// watch; any other refusal makes the watch blind.
        fn rewatch(&self, state: &mut State) {
            let resolved = std::fs::canonicalize(&self.path).ok();
            for path in std::iter::once(&self.path).chain(&resolved) {
                let mut child = path.as_path();
                while let Some(parent) = child.parent() {
                    // Only a `..` has no name: the kernel looks it up, but never as an entry.
                    let name = child.file_name().unwrap_or(OsStr::new(".."));
                    if let Some(wd) = self.add(state, parent) {
                        let names = state.directories.entry(wd).or_default();
                        if !names.iter().any(|n| n == name) {
                            names.push(name.to_owned());
                        }
                    }
                    child = parent;
                }
            }
            if state.directories.len() > MAX_WATCHES {
                state.blind(&"too many watches: the path's directories keep being replaced");
            }
        }

        fn add(&self, state: &mut State, path: &Path) -> Option<i32> {
            let text = CString::new(path.as_os_str().as_bytes()).ok()?;
            // SAFETY: a NUL-terminated path; the result is checked.
            let wd = unsafe { libc::inotify_add_watch(self.queue.as_raw_fd(), text.as_ptr(), DIRECTORY) };
            if wd >= 0 {
                // SAFETY: a NUL-terminated path and a struct the call fills; checked.
                let mut fs: libc::statfs = unsafe { std::mem::zeroed() };
                let kind = match unsafe { libc::statfs(text.as_ptr(), &mut fs) } {
                    0 => fs.f_type as u64 & 0xFFFF_FFFF,
                    _ => 0,
                };
                if !LOCAL.contains(&kind) {
                    state.blind(&format_args!(
                        "{} is on a file system ({kind:#x}) whose changes may not be reported here",
                        path.display()
                    ));
                }
                return Some(wd);
            }
            let error = std::io::Error::last_os_error();
            match error.raw_os_error() {
                Some(libc::ENOENT | libc::ENOTDIR) => {}
                _ => state.blind(&error),
            }
            None
        }
    }

    impl State {
        fn blind(&mut self, why: &dyn std::fmt::Display) {
            if !self.blind {
                tracing::info!(reason = %why, "the database path is stat'ed per request from now on");
            }
            self.blind = true;
        }

        /// Whether an event may change what the path names.
        fn matters(&mut self, wd: i32, mask: u32, name: &OsStr) -> bool {
            if mask & libc::IN_Q_OVERFLOW != 0 {
                // Events were lost: whatever they said is unknown, so the path is stat'ed.
                return true;
            }
            let ended = mask & libc::IN_IGNORED != 0;
            let Some(names) = self.directories.get(&wd) else {
                return false;
            };
            let matters = mask & (libc::IN_MOVE_SELF | libc::IN_DELETE_SELF | libc::IN_UNMOUNT) != 0
                || ended
                || names.iter().any(|n| n == name);
            if ended {
                self.directories.remove(&wd);
            }
            matters
        }
    }
}

#[cfg(test)]
mod tests {
    use std::fs;
    use std::os::unix::fs::{PermissionsExt, symlink};
    use std::path::Path;

    use proptest::prelude::*;

    use super::FileIdentity;

    /// The check a request makes agrees with a `stat` made now, and says the same.
    fn agrees(file: &FileIdentity) -> Result<(), String> {
        let checked = file.check().map_err(|e| e.to_string());
        let stated = file.stat().map_err(|e| e.to_string());
        assert_eq!(
            checked,
            stated,
            "the check disagrees with a stat of {}",
            file.path.display()
        );
        checked
    }

    /// Puts a new file at `to` in one rename, as a restore of a backup does.
    fn replace_with(to: &Path, bytes: &[u8]) {
        let staged = to.with_extension("staged");
        fs::write(&staged, bytes).unwrap();
        fs::rename(&staged, to).unwrap();
    }

    /// Renames `from` to `to` and back: gone in between, the same file again after.
    fn away_and_back(file: &FileIdentity, from: &Path, to: &Path) {
        fs::rename(from, to).unwrap();
        assert!(agrees(file).unwrap_err().contains("is gone"));
        fs::rename(to, from).unwrap();
        assert_eq!(agrees(file), Ok(()));
    }

    #[test]
    fn each_way_of_deleting_or_replacing_the_file_is_seen_by_the_next_check() {
        let dir = tempfile::tempdir().unwrap();
        let db = dir.path().join("scruple.db");
        fs::write(&db, b"norms").unwrap();
        let file = FileIdentity::of(&db).unwrap();
        assert!(file.watched(), "inotify is available to tests on Linux");
        assert_eq!(agrees(&file), Ok(()));

        let away = dir.path().join("away.db");
        away_and_back(&file, &db, &away);

        // Changes that leave the path naming the file: written, its mode changed, a file made
        // and removed beside it.
        fs::write(&db, b"more norms").unwrap();
        fs::set_permissions(&db, fs::Permissions::from_mode(0o600)).unwrap();
        fs::write(dir.path().join("scruple.db-wal"), b"").unwrap();
        fs::remove_file(dir.path().join("scruple.db-wal")).unwrap();
        assert_eq!(agrees(&file), Ok(()));
        assert!(file.watched());

        // Another file renamed over it, as a restore from a copy does.
        fs::hard_link(&db, &away).unwrap();
        replace_with(&db, b"an old copy");
        assert!(agrees(&file).unwrap_err().contains("replaced"));
        // The original put back in place.
        fs::rename(&away, &db).unwrap();
        assert_eq!(agrees(&file), Ok(()));

        // Deleted, then a new file made at the path.
        fs::hard_link(&db, &away).unwrap();
        fs::remove_file(&db).unwrap();
        assert!(agrees(&file).unwrap_err().contains("is gone"));
        fs::write(&db, b"").unwrap();
        assert!(agrees(&file).unwrap_err().contains("replaced"));
        assert!(file.watched(), "no change here needs a stat per request");
    }

    #[test]
    fn a_directory_on_the_path_replaced_or_a_link_on_it_turned_is_seen_by_the_next_check() {
        let root = tempfile::tempdir().unwrap();
        let (live, other) = (root.path().join("live"), root.path().join("other"));
        fs::create_dir_all(live.join("data")).unwrap();
        fs::create_dir_all(other.join("data")).unwrap();
        fs::write(live.join("data/scruple.db"), b"norms").unwrap();
        fs::write(other.join("data/scruple.db"), b"a copy").unwrap();
        // The path goes through a link, as a deployment's `current` release does.
        let link = root.path().join("current");
        symlink(&live, &link).unwrap();
        let file = FileIdentity::of(&link.join("data/scruple.db")).unwrap();
        assert_eq!(agrees(&file), Ok(()));

        // The link turned to another release, in one rename.
        let staged = root.path().join("staged");
        symlink(&other, &staged).unwrap();
        fs::rename(&staged, &link).unwrap();
        assert!(agrees(&file).unwrap_err().contains("replaced"));
        symlink(&live, &staged).unwrap();
        fs::rename(&staged, &link).unwrap();
        assert_eq!(agrees(&file), Ok(()));

        // A directory the link leads to swapped for another.
        fs::rename(live.join("data"), live.join("data.old")).unwrap();
        assert!(agrees(&file).unwrap_err().contains("is gone"));
        fs::rename(other.join("data"), live.join("data")).unwrap();
        assert!(agrees(&file).unwrap_err().contains("replaced"));
        fs::rename(live.join("data"), other.join("data")).unwrap();
        fs::rename(live.join("data.old"), live.join("data")).unwrap();
        assert_eq!(agrees(&file), Ok(()));

        // The directory above the link's target renamed away and back.
        away_and_back(&file, &live, &root.path().join("moved"));
        assert!(file.watched());
    }

    #[test]
    fn a_path_on_a_file_system_not_known_to_report_every_change_is_stated_per_request() {
        // procfs: the kernel writes it, no watch reports it.
        let file = FileIdentity::of(Path::new("/proc/version")).unwrap();
        assert!(!file.watched());
        assert_eq!(agrees(&file), Ok(()));
    }

    #[test]
    fn a_deletion_whose_event_the_full_queue_dropped_is_seen_by_the_next_check() {
        let dir = tempfile::tempdir().unwrap();
        let db = dir.path().join("scruple.db");
        fs::write(&db, b"norms").unwrap();
        let file = FileIdentity::of(&db).unwrap();
        assert_eq!(agrees(&file), Ok(()));
        // Churn beside the file, with no check in between, until the kernel's queue is full
        // (`max_queued_events`, 16,384 by default) and drops what comes next.
        let limit: usize = fs::read_to_string("/proc/sys/fs/inotify/max_queued_events")
            .ok()
            .and_then(|text| text.trim().parse().ok())
            .unwrap_or(16_384);
        let churn = dir.path().join("churn");
        for _ in 0..limit / 2 + 1 {
            fs::write(&churn, b"").unwrap();
            fs::remove_file(&churn).unwrap();
        }
        // The rename's own event is lost: only the overflow is queued.
        away_and_back(&file, &db, &dir.path().join("away.db"));
        assert!(file.watched(), "a lost event costs one stat, not the watch");
    }

    #[test]
    fn a_path_deeper_than_the_watches_allowed_is_stated_per_request() {
        let root = tempfile::tempdir().unwrap();
        let mut deep = root.path().to_path_buf();
        for _ in 0..300 {
            deep.push("d");
        }
        fs::create_dir_all(&deep).unwrap();
        let db = deep.join("scruple.db");
        fs::write(&db, b"norms").unwrap();
        let file = FileIdentity::of(&db).unwrap();
        assert!(!file.watched());
        assert_eq!(agrees(&file), Ok(()));
        away_and_back(&file, &db, &deep.join("away.db"));
    }

    #[test]
    fn odd_directory_names_on_the_path_are_watched_like_any_other() {
        use std::ffi::OsStr;
        use std::os::unix::ffi::OsStrExt;
        let root = tempfile::tempdir().unwrap();
        // Not UTF-8, a line break, spaces and a leading dash, letters outside ASCII, and a
        // `..` the kernel resolves.
        let odd = root
            .path()
            .join(OsStr::from_bytes(b"not-\xff-utf8"))
            .join("two\nlines")
            .join(" -spaced ")
            .join("données");
        fs::create_dir_all(odd.join("sub")).unwrap();
        fs::write(odd.join("scruple.db"), b"norms").unwrap();
        let file = FileIdentity::of(&odd.join("sub/../scruple.db")).unwrap();
        assert!(file.watched());
        assert_eq!(agrees(&file), Ok(()));
        away_and_back(&file, &odd.join("scruple.db"), &root.path().join("away.db"));
        // The directory `..` leaves renamed: the path no longer resolves.
        away_and_back(&file, &odd.join("sub"), &odd.join("elsewhere"));
        // The odd directory itself swapped for a copy.
        let copy = root.path().join("copy");
        fs::create_dir_all(copy.join("sub")).unwrap();
        fs::write(copy.join("scruple.db"), b"a copy").unwrap();
        fs::rename(&odd, root.path().join("kept")).unwrap();
        fs::rename(&copy, &odd).unwrap();
        assert!(agrees(&file).unwrap_err().contains("replaced"));
        fs::rename(&odd, &copy).unwrap();
        fs::rename(root.path().join("kept"), &odd).unwrap();
        assert_eq!(agrees(&file), Ok(()));
        assert!(file.watched());
    }

    /// A change to the tree a path goes through.
    #[derive(Clone, Debug)]
    enum Change {
        /// The file at the path deleted.
        Delete,
        /// The opened file linked back in at the path (over whatever is there).
        Restore,
        /// A new file renamed over the path.
        Copy,
        /// The file written to.
        Write,
        /// A file made or removed beside it.
        Sibling,
        /// The path's directory renamed away (a new, empty one made in its place when `true`).
        MoveDirectory(bool),
        /// The link the path goes through turned to directory 0 or 1.
        Turn(bool),
    }

    fn change() -> impl Strategy<Value = Change> {
        prop_oneof![
            Just(Change::Delete),
            Just(Change::Restore),
            Just(Change::Copy),
            Just(Change::Write),
            Just(Change::Sibling),
            any::<bool>().prop_map(Change::MoveDirectory),
            any::<bool>().prop_map(Change::Turn),
        ]
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(64))]

        /// Whatever is done to the path, the next check says what a `stat` says: the watch
        /// never lets a request through that a `stat` would have stopped, nor the reverse.
        #[test]
        fn the_check_after_any_change_agrees_with_a_stat(changes in proptest::collection::vec(change(), 1..24)) {
            let root = tempfile::tempdir().unwrap();
            let at = |part: &str| root.path().join(part);
            for release in ["r0", "r1"] {
                fs::create_dir_all(at(release).join("data")).unwrap();
            }
            fs::write(at("r0/data/scruple.db"), b"norms").unwrap();
            // A second name for the opened file, so that it can be put back.
            fs::hard_link(at("r0/data/scruple.db"), at("kept")).unwrap();
            symlink(at("r0"), at("current")).unwrap();
            let path = at("current/data/scruple.db");
            let file = FileIdentity::of(&path).unwrap();
            agrees(&file).unwrap();
            for (step, change) in changes.into_iter().enumerate() {
                let data = fs::canonicalize(at("current")).unwrap().join("data");
                // Each change may fail when the tree does not allow it (nothing to delete):
                // the check must agree with a stat either way.
                let _ = match change {
                    Change::Delete => fs::remove_file(&path),
                    Change::Restore => fs::hard_link(at("kept"), at("staged")).and_then(|()| fs::rename(at("staged"), &path)),
                    Change::Copy => fs::write(at("staged"), b"a copy").and_then(|()| fs::rename(at("staged"), &path)),
                    Change::Write => fs::OpenOptions::new().append(true).open(&path).and_then(|mut f| std::io::Write::write_all(&mut f, b"+")),
                    Change::Sibling => match fs::remove_file(data.join("other")) {
                        Ok(()) => Ok(()),
                        Err(_) => fs::write(data.join("other"), b""),
                    },
                    Change::MoveDirectory(fresh) => fs::rename(&data, data.with_file_name(format!("data.{step}")))
                        .and_then(|()| if fresh { fs::create_dir(&data) } else { Ok(()) }),
                    Change::Turn(to) => symlink(at(if to { "r1" } else { "r0" }), at("staged"))
                        .and_then(|()| fs::rename(at("staged"), at("current"))),
                };
                let _ = agrees(&file);
            }
        }
    }
}

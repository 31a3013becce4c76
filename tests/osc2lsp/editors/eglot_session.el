;;; eglot_session.el --- a scripted batch Emacs session with Eglot against osc2lsp  -*- lexical-binding: t; -*-

;; emacs --batch -l eglot_session.el   with OSC2LSP_SPEC=<spec.json>
;;
;; The spec names the server command, the file to open, the edits to make (buffer
;; edits, which Eglot sends as incremental changes) and where to write what the
;; session saw: every diagnostics push, the diagnostics as Eglot places them in the
;; buffer once they equal the expected ones (or at the deadline), the formatting
;; options Eglot sends and the buffer after formatting, and whether the server
;; process ended with the session.

(require 'cl-lib)
(require 'json)
(require 'seq)
(require 'eglot)

(defvar osc2-spec
  (let ((json-object-type 'plist) (json-array-type 'vector) (json-key-type 'keyword))
    (json-read-file (getenv "OSC2LSP_SPEC"))))

(defvar osc2-result nil "What the session saw (a plist, written as JSON).")
(defvar osc2-pushes nil "Every publishDiagnostics the client received, newest first.")

(define-derived-mode osc2-mode prog-mode "OSC2" "Buffers of OpenSCENARIO DSL files.")

(advice-add 'eglot-handle-notification :before
            (lambda (_server method &rest params)
              (when (eq method 'textDocument/publishDiagnostics)
                (push (list :uri (plist-get params :uri)
                            :version (plist-get params :version)
                            :diagnostics (prin1-to-string (plist-get params :diagnostics)))
                      osc2-pushes))))

(defun osc2-wait (predicate)
  "Wait for PREDICATE (reading the server's output) until the spec's deadline."
  (let ((deadline (+ (float-time) (/ (plist-get osc2-spec :timeout_ms) 1000.0))))
    (while (and (not (funcall predicate)) (< (float-time) deadline))
      (accept-process-output nil 0.02))
    (funcall predicate)))

(defun osc2-latest-diagnostics ()
  "The newest push for this buffer's file, as a vector of [line column code message]:
line from 0, column in characters, both where Eglot places the diagnostic in the
buffer; nil before the first push."
  (let* ((uri (eglot--path-to-uri (buffer-file-name)))
         (push (cl-find uri osc2-pushes :key (lambda (p) (plist-get p :uri)) :test #'equal))
         (found nil))
    (when push
      (seq-doseq (diag (car (read-from-string (plist-get push :diagnostics))))
        (let ((beg (car (eglot--range-region (plist-get diag :range)))))
          (save-excursion
            (goto-char beg)
            (push (vector (1- (line-number-at-pos)) (current-column)
                          (plist-get diag :code) (plist-get diag :message))
                  found))))
      (vconcat
       (sort found (lambda (a b)
                     (or (< (aref a 0) (aref b 0))
                         (and (= (aref a 0) (aref b 0))
                              (or (< (aref a 1) (aref b 1))
                                  (and (= (aref a 1) (aref b 1))
                                       (string< (aref a 2) (aref b 2))))))))))))

(defun osc2-same (a b)
  "Whether the diagnostics A (nil: no push yet) equal B."
  (and a (equal a b)))

(defun osc2-finish ()
  (with-temp-file (plist-get osc2-spec :result)
    (insert (json-encode osc2-result)))
  (kill-emacs 0))

(condition-case err
    (let* ((file (plist-get osc2-spec :file))
           (buffer (find-file-noselect file))
           (eglot-sync-connect t)
           server)
      (with-current-buffer buffer
        (osc2-mode)
        (setq server
              (eglot '(osc2-mode)
                     (cons 'transient (file-name-as-directory (plist-get osc2-spec :root)))
                     'eglot-lsp-server
                     (append (plist-get osc2-spec :cmd)
                             (list :initializationOptions
                                   (plist-get osc2-spec :init_options)))
                     "osc2"))
        (setq osc2-result (plist-put osc2-result :initialized (and server t)))
        ;; Diagnostics of the file as opened.
        (osc2-wait (lambda () (osc2-same (osc2-latest-diagnostics)
                                         (plist-get osc2-spec :expected_before))))
        (setq osc2-result (plist-put osc2-result :before (osc2-latest-diagnostics)))
        (setq osc2-result (plist-put osc2-result :pushes_on_open (vconcat (reverse osc2-pushes))))
        ;; The edits, as a user makes them: [start end new] in characters from 0.
        (seq-doseq (edit (plist-get osc2-spec :edits))
          (goto-char (1+ (aref edit 0)))
          (delete-region (point) (1+ (aref edit 1)))
          (insert (aref edit 2))
          (eglot--signal-textDocument/didChange))
        (setq osc2-result (plist-put osc2-result :text
                                     (buffer-substring-no-properties (point-min) (point-max))))
        (osc2-wait (lambda () (osc2-same (osc2-latest-diagnostics)
                                         (plist-get osc2-spec :expected_after))))
        (setq osc2-result (plist-put osc2-result :after (osc2-latest-diagnostics)))
        (setq osc2-result (plist-put osc2-result :pushes (vconcat (reverse osc2-pushes))))
        ;; Formatting with Emacs' defaults: indent-tabs-mode t, tab-width 8.
        (setq osc2-result (plist-put osc2-result :format_options
                                     (list :tabSize tab-width
                                           :insertSpaces (if indent-tabs-mode :json-false t))))
        (eglot-format-buffer)
        (setq osc2-result (plist-put osc2-result :formatted
                                     (buffer-substring-no-properties (point-min) (point-max))))
        (let ((process (jsonrpc--process server)))
          (eglot-shutdown server)
          (osc2-wait (lambda () (not (process-live-p process))))
          (setq osc2-result (plist-put osc2-result :server_pid (process-id process)))
          (setq osc2-result (plist-put osc2-result :stopped
                                       (if (process-live-p process) :json-false t))))))
  (error (setq osc2-result (plist-put osc2-result :error (format "%S" err)))))
(osc2-finish)

;;; eglot_session.el ends here

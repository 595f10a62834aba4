//! Jobs sent to a Web Worker from the page (the browser only): the worker and its handlers,
//! and a job with a worker of its own, its progress and its outcome.

use std::cell::RefCell;
use std::rc::Rc;

use wasm_bindgen::JsCast;
use wasm_bindgen::prelude::{Closure, JsValue};

/// A Web Worker running `web/worker.js`, with the handlers that hear it; dropped, it
/// stops.
pub struct Spawned {
    worker: web_sys::Worker,
    _on_message: Closure<dyn FnMut(web_sys::MessageEvent)>,
    _on_error: Closure<dyn FnMut(web_sys::Event)>,
}

impl Drop for Spawned {
    fn drop(&mut self) {
        self.worker.terminate();
    }
}

impl Spawned {
    /// Starts `web/worker.js`; `on_message` hears every message it sends (its data),
    /// `on_error` why it failed, if it does.
    pub fn new(
        mut on_message: impl FnMut(JsValue) + 'static,
        mut on_error: impl FnMut(String) + 'static,
    ) -> Result<Self, String> {
        let options = web_sys::WorkerOptions::new();
        options.set_type(web_sys::WorkerType::Module);
        let worker =
            web_sys::Worker::new_with_options("./worker.js", &options).map_err(describe)?;
        let on_message = Closure::<dyn FnMut(web_sys::MessageEvent)>::new(
            move |event: web_sys::MessageEvent| on_message(event.data()),
        );
        let on_error = Closure::<dyn FnMut(web_sys::Event)>::new(move |event: web_sys::Event| {
            let message = event
                .dyn_ref::<web_sys::ErrorEvent>()
                .map(|error| error.message())
                .unwrap_or_else(|| "worker.js could not be loaded".to_owned());
            on_error(format!("the background worker failed: {message}"));
        });
        worker.set_onmessage(Some(on_message.as_ref().unchecked_ref()));
        worker.set_onerror(Some(on_error.as_ref().unchecked_ref()));
        Ok(Self {
            worker,
            _on_message: on_message,
            _on_error: on_error,
        })
    }

    /// Sends `job` (an object of named fields, see `web/worker.js`), handing over the
    /// buffers in `transfer`, with the page's compiled module (so the worker need not
    /// compile it again).
    pub fn post(&self, job: &[(&str, JsValue)], transfer: &[JsValue]) -> Result<(), String> {
        let message = js_sys::Object::new();
        let module = ("module", wasm_bindgen::module());
        for (name, value) in job.iter().chain([&module]) {
            js_sys::Reflect::set(&message, &JsValue::from_str(name), value).map_err(describe)?;
        }
        let transfer: js_sys::Array = transfer.iter().collect();
        self.worker
            .post_message_with_transfer(&message, &transfer)
            .map_err(describe)
    }
}

fn describe(error: JsValue) -> String {
    format!("{error:?}")
}

/// A field of a worker's message, if it has it.
pub fn field(data: &JsValue, name: &str) -> Option<JsValue> {
    js_sys::Reflect::get(data, &JsValue::from_str(name))
        .ok()
        .filter(|value| !value.is_undefined())
}

/// A job running in a Web Worker of its own; dropping it stops the worker.
pub type WorkerJob = Spawned;

/// What a worker sends back: its result's bytes (a typed array), or why there is none.
pub type Outcome = Result<JsValue, String>;

/// What a worker says before it is done.
pub enum Report {
    /// How far it got, per mille.
    Progress(u32),
}

/// What hears a job's outcome, shared by the handlers that may hear it.
type OnDone = Rc<RefCell<Option<Box<dyn FnOnce(Outcome)>>>>;

/// Starts a worker of its own on `job` (see [`Spawned::post`]), handing it the buffers in
/// `transfer`; `on_report` hears what it reports on the way, `on_done` its outcome, once.
pub fn start(
    job: &[(&str, JsValue)],
    transfer: &[JsValue],
    on_report: impl Fn(Report) + 'static,
    on_done: impl FnOnce(Outcome) + 'static,
) -> Result<WorkerJob, String> {
    // Called once, by whichever of the message and error handlers hears the end first.
    let on_done: OnDone = Rc::new(RefCell::new(Some(Box::new(on_done))));
    let finish = move |outcome: Outcome| {
        if let Some(on_done) = on_done.borrow_mut().take() {
            on_done(outcome);
        }
    };
    let finish_on_error = finish.clone();
    let spawned = Spawned::new(
        move |data| {
            if let Some(progress) = field(&data, "progress").and_then(|value| value.as_f64()) {
                on_report(Report::Progress(progress as u32));
            } else if let Some(done) = field(&data, "done") {
                finish(Ok(done));
            } else {
                let problem = field(&data, "problem").and_then(|value| value.as_string());
                finish(Err(
                    problem.unwrap_or_else(|| "the worker sent nothing".to_owned())
                ));
            }
        },
        move |problem| finish_on_error(Err(problem)),
    )?;
    spawned.post(job, transfer)?;
    Ok(spawned)
}

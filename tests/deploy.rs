//! The shipped deployment files: the Kubernetes Indexed Job parses and maps completion indices
//! to the same frames as Slurm array tasks; the Slurm batch script takes its shard from the
//! array environment.

use std::collections::HashMap;
use std::path::PathBuf;

use penumbra::batch::{Shard, Split};
use penumbra::script::FrameRange;
use serde_norway::Value;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The documents of a multi-document YAML file.
fn documents(path: &str) -> Vec<Value> {
    let text = std::fs::read_to_string(root().join(path)).unwrap_or_else(|e| panic!("{path}: {e}"));
    serde_norway::Deserializer::from_str(&text)
        .map(|d| serde::Deserialize::deserialize(d).unwrap_or_else(|e| panic!("{path}: {e}")))
        .collect()
}

fn env_of(container: &Value) -> HashMap<String, String> {
    container["env"]
        .as_sequence()
        .map(|vars| {
            vars.iter()
                .filter_map(|v| Some((v["name"].as_str()?.to_owned(), v["value"].as_str()?.to_owned())))
                .collect()
        })
        .unwrap_or_default()
}

/// The words of a container's command and arguments.
fn words(container: &Value) -> Vec<String> {
    ["command", "args"]
        .iter()
        .filter_map(|k| container[*k].as_sequence())
        .flatten()
        .filter_map(|w| w.as_str())
        .flat_map(|w| w.split_whitespace().map(str::to_owned).collect::<Vec<_>>())
        .collect()
}

#[test]
fn the_kubernetes_job_is_indexed_and_maps_indices_like_slurm_tasks() {
    let docs = documents("deploy/k8s/render-job.yaml");
    let job = docs.iter().find(|d| d["kind"].as_str() == Some("Job")).expect("a Job document");
    assert_eq!(job["apiVersion"].as_str(), Some("batch/v1"));
    let spec = &job["spec"];
    assert_eq!(spec["completionMode"].as_str(), Some("Indexed"));
    let completions = spec["completions"].as_u64().expect("completions") as u32;
    assert!(completions >= 2);
    let container = &spec["template"]["spec"]["containers"][0];
    let env = env_of(container);
    assert_eq!(env.get("PENUMBRA_SHARD_COUNT").map(String::as_str), Some(completions.to_string().as_str()));
    let words = words(container);
    assert!(words.iter().any(|w| w == "animate"), "{words:?}");
    assert!(!words.iter().any(|w| w == "--shard"), "the shard comes from JOB_COMPLETION_INDEX: {words:?}");
    let restart = spec["template"]["spec"]["restartPolicy"].as_str();
    assert!(matches!(restart, Some("Never") | Some("OnFailure")), "{restart:?}");
    // The frames volume is shared: a ReadWriteMany claim.
    let claim = docs.iter().find(|d| d["kind"].as_str() == Some("PersistentVolumeClaim")).expect("a PVC");
    let modes: Vec<&str> =
        claim["spec"]["accessModes"].as_sequence().unwrap().iter().filter_map(|m| m.as_str()).collect();
    assert!(modes.contains(&"ReadWriteMany"), "{modes:?}");

    // Completion index i renders what Slurm array task i of the same count renders.
    let range = FrameRange::new(0, 119);
    for i in 0..completions {
        let k8s =
            [("JOB_COMPLETION_INDEX", i.to_string()), ("PENUMBRA_SHARD_COUNT", completions.to_string())];
        let slurm = [
            ("SLURM_ARRAY_TASK_ID", i.to_string()),
            ("SLURM_ARRAY_TASK_MIN", "0".to_owned()),
            ("SLURM_ARRAY_TASK_MAX", (completions - 1).to_string()),
        ];
        let lookup = |vars: &[(&str, String)]| {
            let vars: HashMap<String, String> =
                vars.iter().map(|(k, v)| (k.to_string(), v.clone())).collect();
            move |k: &str| vars.get(k).cloned()
        };
        let from_k8s = Shard::from_env(lookup(&k8s), None).unwrap().unwrap();
        let from_slurm = Shard::from_env(lookup(&slurm), None).unwrap().unwrap();
        assert_eq!(from_k8s, from_slurm);
        for split in [Split::Contiguous, Split::Interleaved] {
            assert_eq!(from_k8s.frames(range, split), from_slurm.frames(range, split));
        }
    }
}

#[test]
fn the_slurm_script_is_an_array_that_leaves_the_shard_to_the_environment() {
    let text = std::fs::read_to_string(root().join("deploy/slurm/render.sbatch")).unwrap();
    assert!(text.starts_with("#!"), "a batch script starts with a shebang");
    assert!(text.lines().any(|l| l.starts_with("#SBATCH --array=")), "a job array");
    assert!(text.contains("RAYON_NUM_THREADS") && text.contains("SLURM_CPUS_PER_TASK"));
    let run = text.lines().find(|l| l.contains(" animate ")).expect("runs penumbra animate");
    assert!(!run.contains("--shard "), "{run}");
}

/// Shell words of a command line: whitespace-separated, double quotes grouping (no escapes).
fn shell_words(line: &str) -> Vec<String> {
    let (mut words, mut word, mut quoted) = (Vec::new(), None::<String>, false);
    for c in line.chars() {
        match c {
            '"' => {
                quoted = !quoted;
                word.get_or_insert_with(String::new);
            }
            c if c.is_whitespace() && !quoted => words.extend(word.take()),
            c => word.get_or_insert_with(String::new).push(c),
        }
    }
    words.extend(word);
    words
}

/// A command and the variables it sets inline before `sbatch`.
type Submission = (String, HashMap<String, String>);

/// Every `sbatch … render.sbatch` command of `text` (the lines of its code blocks and script
/// comments, and its inline code spans), with the variables it sets inline.
fn sbatch_submissions(text: &str) -> Vec<Submission> {
    let mut commands: Vec<&str> = Vec::new();
    for line in text.lines() {
        let line = line.trim_start_matches('#').trim();
        let spans: Vec<&str> = line.split('`').skip(1).step_by(2).collect();
        commands.extend(if spans.is_empty() { vec![line] } else { spans });
    }
    commands
        .into_iter()
        .filter(|c| c.contains("sbatch ") && c.contains("render.sbatch"))
        .map(|command| {
            let command = command.split(" # ").next().unwrap_or(command).trim();
            let vars = shell_words(command)
                .into_iter()
                .take_while(|w| w != "sbatch")
                .filter_map(|w| w.split_once('=').map(|(k, v)| (k.to_owned(), v.to_owned())))
                .collect();
            (command.to_owned(), vars)
        })
        .collect()
}

/// Asserts that each resubmission sets the `FRAMES` and `OUT` that `first` set, so it renders
/// the same frames into the same folder.
fn assert_same_frames_and_out(what: &str, first: &Submission, resubmissions: &[Submission]) {
    assert!(!resubmissions.is_empty(), "{what}: no resubmission");
    for key in ["FRAMES", "OUT"] {
        assert!(first.1.contains_key(key), "{what}: `{}` sets no {key}", first.0);
        for (command, vars) in resubmissions {
            assert_eq!(
                vars.get(key),
                first.1.get(key),
                "{what}: `{command}` does not pass {key} as submitted"
            );
        }
    }
}

#[test]
fn the_readmes_slurm_resubmissions_pass_the_frames_and_folder_of_the_first_submission() {
    let readme = std::fs::read_to_string(root().join("README.md")).unwrap();
    let start = readme.find("**Slurm.**").expect("the README has a Slurm section");
    let end = start + readme[start..].find("**Kubernetes.**").unwrap_or(readme.len() - start);
    let section = &readme[start..end];
    let submissions = sbatch_submissions(section);
    assert!(submissions.len() >= 3, "{submissions:?}");
    assert_same_frames_and_out("README", &submissions[0], &submissions[1..]);
    // `penumbra status` looks at the folder the frames went to.
    let out = &submissions[0].1["OUT"];
    assert!(section.contains(&format!("penumbra status {out}")), "penumbra status is not run on {out}");
}

#[test]
fn the_slurm_scripts_resubmission_examples_pass_the_frames_and_folder_of_its_submit_example() {
    let text = std::fs::read_to_string(root().join("deploy/slurm/render.sbatch")).unwrap();
    let resubmitting = text.find("# Resubmitting").expect("the script explains resubmission");
    let submitted = sbatch_submissions(&text[..resubmitting]);
    let first =
        submitted.iter().find(|(_, vars)| vars.contains_key("FRAMES")).expect("a submit example with FRAMES");
    let resubmissions = sbatch_submissions(&text[resubmitting..]);
    assert!(resubmissions.len() >= 2, "{resubmissions:?}");
    assert_same_frames_and_out("render.sbatch", first, &resubmissions);
}

#[test]
fn shell_words_group_quotes_and_sbatch_submissions_read_inline_variables() {
    assert_eq!(shell_words(r#"A=1 B="x y" C="" sbatch  z"#), ["A=1", "B=x y", "C=", "sbatch", "z"]);
    let found =
        sbatch_submissions("run `A=1 sbatch r.sbatch` or\n```sh\nsbatch x/render.sbatch # again\n```\n");
    assert_eq!(found, [("sbatch x/render.sbatch".to_owned(), HashMap::new())]);
    let found = sbatch_submissions("`A=1 EXTRA_ARGS=\"--shard 1/2\" sbatch --array=1 render.sbatch`\n");
    assert_eq!(found.len(), 1);
    assert_eq!(found[0].1["A"], "1");
    assert_eq!(found[0].1["EXTRA_ARGS"], "--shard 1/2");
}

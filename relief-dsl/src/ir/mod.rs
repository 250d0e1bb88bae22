//! A typed builder over naga IR, in the spirit of cranelift-frontend's `FunctionBuilder`.
//!
//! The builder owns every `Emit` range, block scope and local variable: stage code writes
//! arithmetic with Rust operators on [`Val`]s, declares mutable state with [`FnBuilder::var`],
//! and structures control flow with closures ([`FnBuilder::repeat`], [`FnBuilder::if_`]). It never
//! sees a `naga::Statement`.
//!
//! Values carry their shader type as a Rust type parameter, so `vec2 + f32` either splats
//! (where WGSL would) or does not compile. Host constants fold in Rust: `1.0 / steps as f32`
//! becomes one literal.
//!
//! Resources (textures, samplers, uniforms) are declared lazily, on first use, with the
//! fixed binding numbers of [`crate::abi::binding`], so a module declares only what its
//! stages read; each declaration records what the binding holds in the module's
//! [`Bindings`] table.

mod ops;
pub(crate) mod policy;
mod record;
mod resource;
mod types;
mod values;

use std::cell::{Cell, RefCell};

use crate::abi::AbiRecord;

use naga::{
    Block, Expression, Function, FunctionArgument, FunctionResult, Handle, LocalVariable, Module, Span, Statement,
};

pub use ops::{Float, IntoSame, Ordered};
pub(crate) use policy::{Counting, Plain, Policy, TextureSite};
pub(crate) use record::record;
pub use record::Record;
pub use resource::{BindingEntry, Bindings, Filter, Image, Resource};
pub use types::{FloatVec, Mat4, Ty, UVec2, UVec3, Vec2, Vec3, Vec4};
pub use values::{IntoVal, Val, Var};

/// Module-wide state shared by every function being built: the module itself, the globals
/// already declared in it and what each binding holds. What the composer decides for the
/// code (counting, the level, a wall's textures, the edge constant) is each function's
/// [`Policy`], not this.
pub(crate) struct ModuleCtx {
    pub(crate) module: RefCell<Module>,
    globals: RefCell<Vec<(String, Handle<naga::GlobalVariable>)>>,
    bindings: RefCell<Bindings>,
    /// The first binding declared twice, reported by [`ModuleCtx::finish`].
    clash: RefCell<Option<String>>,
}

/// Names of the probe's private counters.
pub(crate) mod counter {
    /// Loop passes of the coarse stage.
    pub(crate) const COARSE_STEPS: &str = "relief_coarse_steps";
    /// Loop passes of the refine stage.
    pub(crate) const REFINE_STEPS: &str = "relief_refine_steps";
    /// Texture fetches of every stage.
    pub(crate) const FETCHES: &str = "relief_fetches";
}

impl Default for ModuleCtx {
    fn default() -> Self {
        Self::new()
    }
}

impl ModuleCtx {
    /// An empty module.
    pub(crate) fn new() -> Self {
        ModuleCtx {
            module: RefCell::new(Module::default()),
            globals: RefCell::new(Vec::new()),
            bindings: RefCell::new(Bindings::default()),
            clash: RefCell::new(None),
        }
    }

    /// Takes the finished module out, with what each of its bindings holds; two resources
    /// declared at one binding are an error that names both.
    pub(crate) fn finish(self) -> Result<(Module, Bindings), String> {
        match self.clash.into_inner() {
            Some(clash) => Err(clash),
            None => Ok((self.module.into_inner(), self.bindings.into_inner())),
        }
    }

    /// Adds (or finds) a type.
    pub(crate) fn ty(&self, inner: naga::TypeInner) -> Handle<naga::Type> {
        self.module.borrow_mut().types.insert(naga::Type { name: None, inner }, Span::UNDEFINED)
    }

    /// Adds (or finds) a named struct type from `(member name, member type)` pairs, laid out
    /// by naga's own [`naga::proc::Layouter`] (WGSL's alignment rules).
    pub(crate) fn struct_ty(&self, name: &str, members: &[(&str, naga::TypeInner)]) -> Handle<naga::Type> {
        let handles: Vec<Handle<naga::Type>> = members.iter().map(|(_, inner)| self.ty(inner.clone())).collect();
        let mut layouter = naga::proc::Layouter::default();
        layouter.update(self.module.borrow().to_ctx()).expect("member types of relief's structs have layouts");
        let mut offset = 0u32;
        let mut max_align = naga::proc::Alignment::ONE;
        let mut out = Vec::new();
        for ((mname, _), ty) in members.iter().zip(handles) {
            let layout = layouter[ty];
            offset = layout.alignment.round_up(offset);
            max_align = max_align.max(layout.alignment);
            out.push(naga::StructMember { name: Some((*mname).to_string()), ty, binding: None, offset });
            offset += layout.size;
        }
        let span = max_align.round_up(offset);
        self.module.borrow_mut().types.insert(
            naga::Type { name: Some(name.to_string()), inner: naga::TypeInner::Struct { members: out, span } },
            Span::UNDEFINED,
        )
    }

    /// The struct type of one of the ABI's records ([`crate::abi`]), under its Rust name.
    pub(crate) fn record_ty<R: AbiRecord>(&self) -> Handle<naga::Type> {
        let members: Vec<(&str, naga::TypeInner)> =
            R::MEMBERS.iter().map(|(n, m)| (*n, types::member_inner(*m))).collect();
        self.struct_ty(R::NAME, &members)
    }

    /// The global named `name`, declared with `make` the first time it is asked for.
    fn global(
        &self,
        name: &str,
        make: impl FnOnce(&ModuleCtx) -> naga::GlobalVariable,
    ) -> Handle<naga::GlobalVariable> {
        if let Some(h) = self.find_global(name) {
            return h;
        }
        let var = make(self);
        let h = self.module.borrow_mut().global_variables.append(var, Span::UNDEFINED);
        self.globals.borrow_mut().push((name.to_string(), h));
        h
    }

    /// The global `name` in `space` (bound at group 0, `binding`, when it has one), declared
    /// with the type `ty` makes the first time it is asked for: the one place a
    /// `naga::GlobalVariable` is written, so that a stage or entry asks for a global by what
    /// it is.
    fn declare(
        &self,
        name: &str,
        space: naga::AddressSpace,
        binding: Option<u32>,
        ty: impl FnOnce(&ModuleCtx) -> Handle<naga::Type>,
    ) -> Handle<naga::GlobalVariable> {
        self.global(name, |m| naga::GlobalVariable {
            name: Some(name.to_string()),
            space,
            binding: binding.map(|binding| naga::ResourceBinding { group: 0, binding }),
            ty: ty(m),
            init: None,
            memory_decorations: Default::default(),
        })
    }

    /// The resource `name` in `space` at group 0, `binding`, declared with the type `ty` makes
    /// the first time it is asked for, and recorded in the module's [`Bindings`] as
    /// `resource`.
    pub(crate) fn bound(
        &self,
        name: &str,
        space: naga::AddressSpace,
        binding: u32,
        resource: Resource,
        ty: impl FnOnce(&ModuleCtx) -> Handle<naga::Type>,
    ) -> Handle<naga::GlobalVariable> {
        if let Some(h) = self.find_global(name) {
            return h;
        }
        let entry = BindingEntry { binding, name: name.to_string(), resource };
        if let Err(clash) = self.bindings.borrow_mut().push(entry) {
            self.clash.borrow_mut().get_or_insert(clash);
        }
        self.declare(name, space, Some(binding), ty)
    }

    /// What each binding declared so far holds.
    pub(crate) fn bindings(&self) -> std::cell::Ref<'_, Bindings> {
        self.bindings.borrow()
    }

    /// The private (per-invocation) global `name` of type `T`, declared on first use.
    pub(crate) fn private<T: Ty>(&self, name: &str) -> Handle<naga::GlobalVariable> {
        self.declare(name, naga::AddressSpace::Private, None, |m| m.ty(T::inner()))
    }

    /// The global already declared under `name`, if any.
    pub(crate) fn find_global(&self, name: &str) -> Option<Handle<naga::GlobalVariable>> {
        self.globals.borrow().iter().find(|(n, _)| n == name).map(|(_, h)| *h)
    }

    /// Starts a function with named, typed arguments (and optional bindings, for entry points),
    /// written under `policy`.
    pub(crate) fn function<'a>(
        &'a self,
        name: &str,
        args: &[(&str, Handle<naga::Type>, Option<naga::Binding>)],
        policy: &'a dyn Policy,
    ) -> FnBuilder<'a> {
        let arguments = args
            .iter()
            .map(|(n, ty, binding)| FunctionArgument {
                name: Some((*n).to_string()),
                ty: *ty,
                binding: binding.clone(),
            })
            .collect();
        FnBuilder {
            ctx: self,
            policy: Cell::new(policy),
            f: RefCell::new(FnState {
                func: Function { name: Some(name.to_string()), arguments, ..Function::default() },
                blocks: vec![Block::new()],
                emit_from: None,
                loop_depth: 0,
                no_level: Vec::new(),
            }),
        }
    }

    /// Adds a finished function to the module.
    pub(crate) fn add_function(&self, f: Function) -> Handle<Function> {
        self.module.borrow_mut().functions.append(f, Span::UNDEFINED)
    }
}

struct FnState {
    func: Function,
    /// Open blocks, innermost last; the first is the function body.
    blocks: Vec<Block>,
    /// Index of the first expression not yet covered by an `Emit`.
    emit_from: Option<usize>,
    loop_depth: u32,
    /// What the function read that has no level while its policy's `lod` is not zero
    /// ([`FnBuilder::no_level`]).
    no_level: Vec<String>,
}

/// The function being built. Stage code receives `&FnBuilder` and builds values through it.
pub struct FnBuilder<'a> {
    pub(crate) ctx: &'a ModuleCtx,
    policy: Cell<&'a dyn Policy>,
    f: RefCell<FnState>,
}

/// The body of a loop ([`FnBuilder::repeat`]): the function being built, inside the loop. Only
/// here can stage code leave the loop or end a pass early, so that a `break_if` outside a
/// loop does not compile:
///
/// ```
/// # use relief_dsl::ir::FnBuilder;
/// fn inside<'a>(s: &'a FnBuilder<'a>) {
///     s.repeat(4, |l| l.break_if(l.lit_bool(true)));
/// }
/// ```
///
/// ```compile_fail
/// # use relief_dsl::ir::FnBuilder;
/// fn outside<'a>(s: &'a FnBuilder<'a>) {
///     s.break_if(s.lit_bool(true)); // no `break_if` on a `FnBuilder`: only a `Loop` has one
/// }
/// ```
///
/// `if_` and `if_else` on a `Loop` hand their branches the `Loop` too, so a branch can leave
/// the loop. Like naga's (and WGSL's), a break or continue acts on the innermost loop.
#[repr(transparent)]
pub struct Loop<'a>(FnBuilder<'a>);

impl<'a> std::ops::Deref for Loop<'a> {
    type Target = FnBuilder<'a>;
    fn deref(&self) -> &FnBuilder<'a> {
        &self.0
    }
}

impl<'a> Loop<'a> {
    /// The stage `s`, seen from inside a loop it is building.
    fn of(s: &'a FnBuilder<'a>) -> &'a Loop<'a> {
        assert!(s.f.borrow().loop_depth > 0, "a loop token outside a loop");
        // SAFETY: `Loop` is `repr(transparent)` over `FnBuilder`, so the two have one layout, and
        // the reference keeps the stage's lifetime.
        unsafe { &*(s as *const FnBuilder<'a> as *const Loop<'a>) }
    }

    fn jump_if(&'a self, cond: Val<'a, bool>, jump: Statement) {
        assert!(self.f.borrow().loop_depth > 0, "a loop token used after its loop");
        let accept = self.block(|s| s.stmt(jump));
        self.stmt(Statement::If { condition: cond.handle(), accept, reject: Block::new() });
    }

    /// Leaves the innermost loop when `cond` holds.
    pub fn break_if(&'a self, cond: Val<'a, bool>) {
        self.jump_if(cond, Statement::Break)
    }

    /// Ends this pass of the innermost loop when `cond` holds (the pass counter still steps:
    /// it lives in the loop's `continuing` block).
    pub fn continue_if(&'a self, cond: Val<'a, bool>) {
        self.jump_if(cond, Statement::Continue)
    }

    /// Ends this pass of the innermost loop (code after it in the pass does not run).
    pub fn continue_(&'a self) {
        self.stmt(Statement::Continue)
    }

    /// `if cond { then }`, the branch still inside the loop.
    pub fn if_(&'a self, cond: Val<'a, bool>, then: impl FnOnce(&'a Loop<'a>)) {
        self.0.if_(cond, |s| then(Loop::of(s)))
    }

    /// `if cond { then } else { otherwise }`, both branches still inside the loop.
    pub fn if_else(
        &'a self,
        cond: Val<'a, bool>,
        then: impl FnOnce(&'a Loop<'a>),
        otherwise: impl FnOnce(&'a Loop<'a>),
    ) {
        self.0.if_else(cond, |s| then(Loop::of(s)), |s| otherwise(Loop::of(s)))
    }
}

fn is_pre_emitted(e: &Expression) -> bool {
    // `CallResult` is produced by its `Call` statement and must not be emitted either.
    e.needs_pre_emit() || matches!(e, Expression::CallResult(_))
}

impl<'a> FnBuilder<'a> {
    /// The module this function belongs to.
    pub(crate) fn module(&self) -> &'a ModuleCtx {
        self.ctx
    }

    /// The composer's policy for the code written now.
    pub(crate) fn policy(&self) -> &'a dyn Policy {
        self.policy.get()
    }

    /// Whether the code written now counts loop passes and fetches (the probe's copy).
    pub(crate) fn counting(&self) -> bool {
        self.policy().step_counter().is_some()
    }

    /// Runs `body` with `policy` in place of the function's own (restored after): a region
    /// of the function that reads another set of textures, as a room's branch per wall.
    pub(crate) fn with_policy<R>(&self, policy: &'a dyn Policy, body: impl FnOnce() -> R) -> R {
        let before = self.policy.replace(policy);
        let out = body();
        self.policy.set(before);
        out
    }

    /// Notes that the function reads `what`, which has no level, while its policy's `lod`
    /// is not zero; the composer turns the notes into an error naming the stage
    /// ([`FnBuilder::take_no_level`]).
    pub(crate) fn no_level(&self, what: &str) {
        if self.policy().lod() != crate::spec::Lod::Zero {
            self.f.borrow_mut().no_level.push(what.to_string());
        }
    }

    /// The notes of [`FnBuilder::no_level`] so far, sorted, each once; the list is emptied.
    pub(crate) fn take_no_level(&self) -> Vec<String> {
        let mut what = std::mem::take(&mut self.f.borrow_mut().no_level);
        what.sort();
        what.dedup();
        what
    }

    /// Appends an expression, keeping the emit bookkeeping.
    pub(crate) fn expr(&self, e: Expression) -> Handle<Expression> {
        let pre = is_pre_emitted(&e);
        let mut f = self.f.borrow_mut();
        if pre {
            Self::flush(&mut f);
            f.func.expressions.append(e, Span::UNDEFINED)
        } else {
            let len = f.func.expressions.len();
            if f.emit_from.is_none() {
                f.emit_from = Some(len);
            }
            f.func.expressions.append(e, Span::UNDEFINED)
        }
    }

    fn flush(f: &mut FnState) {
        if let Some(start) = f.emit_from.take() {
            if start < f.func.expressions.len() {
                let range = f.func.expressions.range_from(start);
                f.blocks.last_mut().unwrap().push(Statement::Emit(range), Span::UNDEFINED);
            }
        }
    }

    /// Appends a statement to the innermost open block, after emitting pending expressions.
    pub(crate) fn stmt(&self, s: Statement) {
        let mut f = self.f.borrow_mut();
        Self::flush(&mut f);
        f.blocks.last_mut().unwrap().push(s, Span::UNDEFINED);
    }

    /// Runs `body` in a fresh block and returns it.
    pub(crate) fn block(&'a self, body: impl FnOnce(&'a Self)) -> Block {
        {
            let mut f = self.f.borrow_mut();
            Self::flush(&mut f);
            f.blocks.push(Block::new());
        }
        body(self);
        let mut f = self.f.borrow_mut();
        Self::flush(&mut f);
        f.blocks.pop().unwrap()
    }

    /// A typed view of an expression handle.
    pub(crate) fn wrap<T: Ty>(&'a self, h: Handle<Expression>) -> Val<'a, T> {
        Val::from_handle(self, h)
    }

    /// The `i`-th argument of the function.
    pub(crate) fn arg<T: Ty>(&'a self, i: u32) -> Val<'a, T> {
        self.wrap(self.expr(Expression::FunctionArgument(i)))
    }

    /// A mutable local variable called `name` in the generated shader, initialised with
    /// `init`.
    pub fn var<T: Ty>(&'a self, name: &str, init: impl IntoVal<'a, T>) -> Var<'a, T> {
        let init = init.into_val(self);
        let ty = self.ctx.ty(T::inner());
        let lv = {
            let mut f = self.f.borrow_mut();
            f.func
                .local_variables
                .append(LocalVariable { name: Some(name.to_string()), ty, init: None }, Span::UNDEFINED)
        };
        let ptr = self.expr(Expression::LocalVariable(lv));
        let var = Var::new(self, ptr);
        var.set(init);
        var
    }

    /// Gives a value a name in the generated shader.
    pub fn name<T: Ty>(&'a self, name: &str, v: Val<'a, T>) -> Val<'a, T> {
        self.f.borrow_mut().func.named_expressions.insert(v.handle(), name.to_string());
        v
    }

    /// `for _ in 0..n { body }`. In the probe variant every pass counts as one iteration.
    ///
    /// The body receives the loop ([`Loop`]): a [`FnBuilder`] (it derefs to one) that can also
    /// leave the loop ([`Loop::break_if`]) or end the pass early ([`Loop::continue_if`]).
    pub fn repeat(&'a self, n: u32, body: impl FnOnce(&'a Loop<'a>)) {
        self.repeat_until(n, None, body)
    }

    /// Like [`FnBuilder::repeat`], but also stops once the pass count reaches `limit` (a run-time
    /// value never above `n`); `n` stays the static bound the loop is known to end by.
    pub fn repeat_up_to(&'a self, n: u32, limit: Val<'a, u32>, body: impl FnOnce(&'a Loop<'a>)) {
        self.repeat_until(n, Some(limit), body)
    }

    fn repeat_until(&'a self, n: u32, limit: Option<Val<'a, u32>>, body: impl FnOnce(&'a Loop<'a>)) {
        let i = self.var::<u32>("i", 0u32);
        self.f.borrow_mut().loop_depth += 1;
        let body_block = self.block(|s| {
            let l = Loop::of(s);
            let i_now = i.get();
            let mut done = i_now.ge(n);
            if let Some(limit) = limit {
                done = done | i_now.ge(limit);
            }
            l.break_if(done);
            if let Some(counter) = s.policy().step_counter() {
                s.count(counter);
            }
            body(l);
        });
        // The pass counter steps in naga's `continuing` block, which runs after every pass,
        // a `continue` included.
        let continuing = self.block(|_| i.set(i + 1u32));
        self.f.borrow_mut().loop_depth -= 1;
        self.stmt(Statement::Loop { body: body_block, continuing, break_if: None });
    }

    /// `if cond { then }`.
    pub fn if_(&'a self, cond: Val<'a, bool>, then: impl FnOnce(&'a Self)) {
        let accept = self.block(then);
        self.stmt(Statement::If { condition: cond.handle(), accept, reject: Block::new() });
    }

    /// `if cond { then } else { otherwise }`.
    pub fn if_else(&'a self, cond: Val<'a, bool>, then: impl FnOnce(&'a Self), otherwise: impl FnOnce(&'a Self)) {
        let accept = self.block(then);
        let reject = self.block(otherwise);
        self.stmt(Statement::If { condition: cond.handle(), accept, reject });
    }

    /// `cond ? a : b`, both sides evaluated.
    pub fn select<T: Ty>(&'a self, cond: Val<'a, bool>, a: impl IntoVal<'a, T>, b: impl IntoVal<'a, T>) -> Val<'a, T> {
        let a = a.into_val(self);
        let b = b.into_val(self);
        self.wrap(self.expr(Expression::Select { condition: cond.handle(), accept: a.handle(), reject: b.handle() }))
    }

    /// Returns from the function (from anywhere in it).
    pub(crate) fn ret_handle(&self, value: Option<Handle<Expression>>) {
        self.stmt(Statement::Return { value });
    }

    /// Adds one to the private counter `name` (probe variant only).
    pub(crate) fn count(&'a self, name: &str) {
        let g = self.ctx.private::<u32>(name);
        let ptr = self.expr(Expression::GlobalVariable(g));
        let v: Val<'a, u32> = self.wrap(self.expr(Expression::Load { pointer: ptr }));
        let next = v + 1u32;
        self.stmt(Statement::Store { pointer: ptr, value: next.handle() });
    }

    /// Calls `function` with `args`; returns the result's handle when it has one.
    pub(crate) fn call(
        &self,
        function: Handle<Function>,
        args: &[Handle<Expression>],
        has_result: bool,
    ) -> Option<Handle<Expression>> {
        let result = if has_result { Some(self.expr(Expression::CallResult(function))) } else { None };
        self.stmt(Statement::Call { function, arguments: args.to_vec(), result });
        result
    }

    /// Finishes the function: the body gets a final `return value`, and the function its
    /// result type.
    pub(crate) fn finish(
        &self,
        result: Option<(Handle<naga::Type>, Option<naga::Binding>, Handle<Expression>)>,
    ) -> Function {
        match result {
            Some((ty, binding, value)) => {
                self.stmt(Statement::Return { value: Some(value) });
                let mut f = self.take_state();
                f.func.result = Some(FunctionResult { ty, binding });
                f.func.body = f.blocks.pop().unwrap();
                f.func
            }
            None => {
                self.stmt(Statement::Return { value: None });
                let mut f = self.take_state();
                f.func.body = f.blocks.pop().unwrap();
                f.func
            }
        }
    }

    fn take_state(&self) -> FnState {
        self.f.replace(FnState {
            func: Function::default(),
            blocks: vec![Block::new()],
            emit_from: None,
            loop_depth: 0,
            no_level: Vec::new(),
        })
    }
}

/// Struct and pointer plumbing, for the composer (stages use the typed structs of
/// [`crate::stage`] instead).
impl<'a> FnBuilder<'a> {
    /// Member `index` of the struct value `base`.
    pub(crate) fn field<T: Ty>(&'a self, base: Handle<Expression>, index: u32) -> Val<'a, T> {
        self.wrap(self.expr(Expression::AccessIndex { base, index }))
    }
    /// A struct value of type `ty` from its members.
    pub(crate) fn make_struct(&self, ty: Handle<naga::Type>, members: &[Handle<Expression>]) -> Handle<Expression> {
        self.expr(Expression::Compose { ty, components: members.to_vec() })
    }
    /// A pointer to the global `g`.
    pub(crate) fn global_ptr(&self, g: Handle<naga::GlobalVariable>) -> Handle<Expression> {
        self.expr(Expression::GlobalVariable(g))
    }
    /// Pointer to the member `name` of the ABI record `R` behind `ptr`, at the position the
    /// record's declaration gives it ([`AbiRecord::member_index`]; panics on a name it lacks).
    pub(crate) fn member_ptr<R: AbiRecord>(&self, ptr: Handle<Expression>, name: &str) -> Handle<Expression> {
        self.expr(Expression::AccessIndex { base: ptr, index: R::member_index(name) })
    }
    /// Pointer to element `index` of the array behind `ptr`.
    pub(crate) fn element_ptr(&self, ptr: Handle<Expression>, index: Handle<Expression>) -> Handle<Expression> {
        self.expr(Expression::Access { base: ptr, index })
    }
    /// Loads through a pointer.
    pub(crate) fn load<T: Ty>(&'a self, ptr: Handle<Expression>) -> Val<'a, T> {
        self.wrap(self.expr(Expression::Load { pointer: ptr }))
    }
    /// Stores through a pointer.
    pub(crate) fn store(&self, ptr: Handle<Expression>, value: Handle<Expression>) {
        self.stmt(Statement::Store { pointer: ptr, value });
    }
    /// Stores each `(name, value)` of `values`, in the order given, into that member of the
    /// ABI record `R` behind `ptr` (a probe entry's hit record). Panics unless `values` names
    /// every member of `R` once.
    pub(crate) fn store_record<R: AbiRecord>(&self, ptr: Handle<Expression>, values: &[(&str, Handle<Expression>)]) {
        let mut stored = vec![false; R::MEMBERS.len()];
        for &(name, value) in values {
            let seen = std::mem::replace(&mut stored[R::member_index(name) as usize], true);
            assert!(!seen, "the ABI record {}: member `{name}` stored twice", R::NAME);
            self.store(self.member_ptr::<R>(ptr, name), value);
        }
        let missing: Vec<&str> = R::MEMBERS.iter().zip(&stored).filter(|(_, s)| !**s).map(|((n, _), _)| *n).collect();
        assert!(missing.is_empty(), "the ABI record {}: members {missing:?} not stored", R::NAME);
    }
    /// Number of elements of the runtime-sized array behind `ptr`.
    pub(crate) fn array_length(&'a self, ptr: Handle<Expression>) -> Val<'a, u32> {
        self.wrap(self.expr(Expression::ArrayLength(ptr)))
    }
    /// Returns from a function without a result.
    pub(crate) fn ret(&self) {
        self.stmt(Statement::Return { value: None });
    }
    /// Discards the fragment (`discard` in WGSL and GLSL): valid in a fragment entry only.
    pub(crate) fn discard(&self) {
        self.stmt(Statement::Kill);
    }
}

#[cfg(test)]
mod tests;

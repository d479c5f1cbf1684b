!> Case-file reader: the whole file, section by section.
!>
!> The top level is checked for unknown and duplicate keys, then each section is read and
!> checked by its own module (mpm_case_domain, mpm_case_materials, ...) through a cursor on
!> the top-level object, in the order below: a section may depend on those before it (the
!> bodies on the domain and the materials, the time step on the bodies). The first error
!> found is returned (code exit_input); every message starts with the case file name.
submodule (mpm_case) mpm_case_reader
    use mpm_strings, only: max_name_bytes, int_text, base_name, join
    use mpm_json, only: json_document_type, json_value_type, json_parse_file, &
        json_parse_string, json_free, json_root, json_is_object
    use mpm_case_cursor, only: cursor_type, new_cursor, input_error, describe
    use mpm_case_domain, only: read_domain, domain_keys, face_keys, axis_names
    use mpm_boundary_registry, only: all_boundary_keys
    use mpm_boundary, only: face_nodes_type
    use mpm_case_particles, only: read_particles, particle_keys
    use mpm_case_materials, only: read_materials
    use mpm_material, only: material_holder_type, material_key_width, key_path_width
    use mpm_material_registry, only: material_models, material_choices, material_choice_codes, &
        keys_of
    use mpm_case_bodies, only: read_bodies, body_keys, round_keys, cylinder_keys
    use mpm_case_sites, only: body_site_count, body_shared_sites
    use mpm_case_states, only: read_states
    use mpm_case_solver, only: read_solver, solver_keys
    use mpm_case_time, only: read_time, time_keys
    use mpm_case_damping, only: read_damping, damping_keys
    use mpm_case_initial_stress, only: read_initial_stress, initial_stress_keys
    use mpm_case_contact, only: read_contact, contact_keys
    use mpm_case_output, only: read_output, output_keys
    use mpm_case_progress, only: read_progress, progress_keys
    use mpm_case_checkpoint, only: read_checkpoint, checkpoint_keys
    use mpm_case_pore_water, only: read_pore_water, pore_water_keys, pore_material_keys, &
        pore_face_pressure_keys
    use mpm_case_guard, only: read_guard, guard_keys
    use mpm_case_loads, only: read_loads, load_keys
    use mpm_time_function, only: time_function_keys
    use mpm_case_motion, only: read_motions, motion_keys
    use mpm_case_strength_reduction, only: read_strength_reduction, strength_reduction_keys
    implicit none

    character(len=*), parameter :: top_keys(*) = [character(len=18) :: "name", "dimension", &
        "domain", "particles", "materials", "bodies", "gravity", "solver", "time", "damping", &
        "contact", "output", "progress", "save_state", "load_state", "checkpoint", "guard", &
        "initial_stress", "loads", "prescribed_motion", "strength_reduction", "pore_water"]
        !! keys of the top level
    integer, parameter :: case_path_width = 80
        !! longest key path case_key_paths can list ("materials[type=...].softening.strain")
    integer, parameter :: max_case_name = max_name_bytes - len(".xdmf.tmp")
        !! longest case name [bytes]: <name>.xdmf.tmp is a file name of the output folder

contains

    module procedure read_case_file
        type(json_document_type) :: doc
        character(len=:), allocatable :: text

        call json_parse_file(path, doc, error, text)
        if (.not. allocated(error)) then
            call resolve_case(json_root(doc), path, base_name(path), case, error)
        end if
        call json_free(doc)
        if (.not. allocated(error)) call move_alloc(text, case%text)
    end procedure read_case_file

    module procedure read_case_string
        type(json_document_type) :: doc
        character(len=:), allocatable :: src, default_name

        src = "<string>"
        default_name = "case"
        if (present(source)) then
            if (len_trim(source) > 0) then
                src = source
                default_name = base_name(source)
            end if
        end if
        call json_parse_string(text, doc, error, src)
        if (.not. allocated(error)) then
            call resolve_case(json_root(doc), src, default_name, case, error)
        end if
        call json_free(doc)
        if (.not. allocated(error)) case%text = text
    end procedure read_case_string

    module procedure case_key_paths
        character(len=case_path_width), allocatable :: list(:)
        character(len=material_key_width), allocatable :: choices(:)
        character(len=key_path_width), allocatable :: sections(:)
        type(material_holder_type), allocatable :: models(:)
        integer, allocatable :: codes(:)
        character(len=:), allocatable :: material
        integer :: i, longest

        ! Every object the reader checks, from the sections' own key lists; a new section
        ! needs its line here too (the schema test then asks for its keys).
        allocate (list(0))
        call add_key_paths(list, "", top_keys)
        call add_key_paths(list, "domain", domain_keys)
        call add_key_paths(list, "domain.boundaries", face_keys)
        do i = 1, size(face_keys)
            call add_key_paths(list, "domain.boundaries."//trim(face_keys(i)), &
                all_boundary_keys())
        end do
        call add_key_paths(list, "particles", particle_keys)
        models = material_models()
        choices = material_choices()
        codes = material_choice_codes()
        do i = 1, size(choices)
            material = "materials[type="//trim(choices(i))//"]"
            call add_key_paths(list, material, keys_of(models(codes(i))%m))
            call models(codes(i))%m%section_keys(sections)
            call add_key_paths(list, material, sections)
        end do
        call add_key_paths(list, "bodies[]", body_keys)
        call add_key_paths(list, "bodies[].circle", round_keys)
        call add_key_paths(list, "bodies[].sphere", round_keys)
        call add_key_paths(list, "bodies[].cylinder", cylinder_keys)
        call add_key_paths(list, "solver", solver_keys)
        call add_key_paths(list, "time", time_keys)
        call add_key_paths(list, "damping", damping_keys)
        call add_key_paths(list, "initial_stress", initial_stress_keys)
        call add_key_paths(list, "loads[]", load_keys)
        call add_key_paths(list, "loads[].time_function", time_function_keys)
        call add_key_paths(list, "prescribed_motion[]", motion_keys)
        call add_key_paths(list, "prescribed_motion[].time_function", time_function_keys)
        call add_key_paths(list, "strength_reduction", strength_reduction_keys)
        call add_key_paths(list, "contact", contact_keys)
        call add_key_paths(list, "output", output_keys)
        call add_key_paths(list, "progress", progress_keys)
        call add_key_paths(list, "checkpoint", checkpoint_keys)
        call add_key_paths(list, "guard", guard_keys)
        call add_key_paths(list, "pore_water", pore_water_keys)
        call add_key_paths(list, "pore_water.materials[]", pore_material_keys)
        call add_key_paths(list, "pore_water.faces", face_keys)
        do i = 1, size(face_keys)
            call add_key_paths(list, "pore_water.faces."//trim(face_keys(i)), &
                pore_face_pressure_keys)
        end do
        longest = 0
        do i = 1, size(list)
            longest = max(longest, len_trim(list(i)))
        end do
        allocate (character(len=longest) :: paths(size(list)))
        do i = 1, size(list)
            paths(i) = list(i)
        end do
    end procedure case_key_paths

    !> Append "path.key" for every key of an object to a list of key paths.
    pure subroutine add_key_paths(list, path, keys)
        character(len=case_path_width), allocatable, intent(inout) :: list(:)
            !! key paths so far
        character(len=*), intent(in) :: path
            !! path of the object ("" at the top level)
        character(len=*), intent(in) :: keys(:)
            !! keys of the object

        integer :: k

        do k = 1, size(keys)
            list = [character(len=case_path_width) :: list, join(path, trim(keys(k)))]
        end do
    end subroutine add_key_paths

    !> Check a parsed document and resolve it into `case`, section by section.
    subroutine resolve_case(top, src, default_name, case, error)
        type(json_value_type), intent(in) :: top
            !! top-level value of the document
        character(len=*), intent(in) :: src
            !! case file name, first word of every message
        character(len=*), intent(in) :: default_name
            !! case name when the file gives none
        type(case_type), intent(out) :: case
            !! resolved case
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        type(cursor_type) :: root
        integer :: i

        case%file = src
        case%contact%type = "none"
        case%save_state = ""
        case%load_state = ""
        case%checkpoint%file = ""
        case%text = ""
        if (.not. json_is_object(top)) then
            call input_error(error, src, "the top level must be a JSON object { ... } holding " &
                //"the case keys, found "//describe(top))
            return
        end if
        root = new_cursor(top, "", src)
        call root%check_keys(top_keys, error)
        if (allocated(error)) return
        call read_name(root, default_name, case%name, error)
        if (allocated(error)) return
        call read_domain(root, case%dim, case%domain, error)
        if (allocated(error)) return
        call read_particles(root, case%dim, case%domain, case%particles, error)
        if (allocated(error)) return
        call read_materials(root, case%materials, error)
        if (allocated(error)) return
        call read_states(root, case%save_state, case%load_state, error)
        if (allocated(error)) return
        if (len(case%load_state) > 0) then
            do i = 1, size(case%materials)
                if (.not. allocated(case%materials(i)%law)) cycle
                if (.not. case%materials(i)%law%needs_initial_state()) cycle
                call root%fail(error, "materials["//int_text(i)//'] "'//case%materials(i)%name &
                    //'"'//" takes a state from the initial position of each particle (a " &
                    //"strength growing with depth), which the state file of load_state does " &
                    //"not keep; start the case from its bodies, or give a constant strength")
                return
            end do
        end if
        call read_bodies(root, case%dim, case%domain, case%particles, case%materials, &
            case%load_state, body_site_count, body_shared_sites, case%bodies, error)
        if (allocated(error)) return
        call root%get_vector("gravity", case%dim, case%gravity, error, unit="m/s2")
        if (allocated(error)) return
        call read_pore_water(root, case%dim, case%gravity, case%materials, case%pore_water, &
            error)
        if (allocated(error)) return
        call read_solver(root, case%solver, error)
        if (allocated(error)) return
        call check_periodic(root, case, error)
        if (allocated(error)) return
        call read_time(root, case%dim, case%domain%dx, case%materials, case%bodies, case%time, &
            error)
        if (allocated(error)) return
        call read_damping(root, case%damping, error)
        if (allocated(error)) return
        call read_initial_stress(root, case%dim, case%gravity, case%materials, case%load_state, &
            case%initial_stress, error)
        if (allocated(error)) return
        if (case%initial_stress%type == initial_k0 .and. allocated(case%bodies)) then
            if (any([(allocated(case%bodies(i)%list), i=1, size(case%bodies))])) then
                call root%fail(error, 'initial_stress.type = "k0" weighs the bodies filled ' &
                    //"on the lattice; a particle_list body gives its particles' stresses in " &
                    //"its columns sxx, syy, ...: remove initial_stress or the list")
                return
            end if
        end if
        call read_loads(root, case%dim, case%domain, case%materials, case%loads, error)
        if (allocated(error)) return
        call read_motions(root, case%dim, case%domain, case%materials, &
            materials_used(case%materials, case%bodies), case%motions, error)
        if (allocated(error)) return
        call check_deformable(root, case, error)
        if (allocated(error)) return
        call read_strength_reduction(root, case%materials, case%strength_reduction, error)
        if (allocated(error)) return
        call read_contact(root, case%contact, error)
        if (allocated(error)) return
        call read_output(root, case%name, case%time%tend, case%output, error)
        if (allocated(error)) return
        call read_progress(root, case%progress, error)
        if (allocated(error)) return
        call read_checkpoint(root, case%checkpoint, error)
        if (allocated(error)) return
        call read_guard(root, case%guard, error)
    end subroutine resolve_case

    !> Periodic faces tie the nodes of two faces, which the shape functions with a boundary
    !> modification (B-splines) or with corners anywhere (CPDI) and the XPIC projection do not
    !> follow, so they are refused with them.
    subroutine check_periodic(root, case, error)
        type(cursor_type), intent(in) :: root
            !! top-level object
        type(case_type), intent(in) :: case
            !! the case, read up to its solver
        type(error_type), allocatable, intent(out) :: error
            !! set when the combination is refused

        integer :: axis, wide
        logical :: periodic
        type(face_nodes_type) :: lower

        periodic = .false.
        wide = 0
        do axis = 1, case%dim
            lower = case%domain%nodes(1, axis, case%dim)
            periodic = periodic .or. lower%periodic
            if (lower%periodic .and. case%domain%ncells(axis) > 1) wide = axis
        end do
        if (.not. periodic) return
        select case (trim(case%solver%shape_function))
        case ("linear")
            continue
        case ("cpgimp", "gimp", "ugimp")
            ! a particle's domain is cut at a face, not carried across it: exact only where
            ! every node of the axis is tied (one cell across)
            if (wide > 0) then
                call root%fail(error, 'solver.shape_function = "' &
                    //trim(case%solver%shape_function)//'" with "periodic" faces '// &
                    axis_names(wide:wide)//"min/"//axis_names(wide:wide)//"max over " &
                    //int_text(case%domain%ncells(wide))//" cells: a GIMP domain is cut " &
                    //'at the face, not carried across it; use "linear", or one cell ' &
                    //"across (a 1D column)")
                return
            end if
        case default
            call root%fail(error, 'solver.shape_function = "'//trim(case%solver%shape_function) &
                //'" with "periodic" faces: the tied faces work with "linear" (and "cpgimp", ' &
                //'"ugimp" one cell across) only (the B-splines change near a face, CPDI ' &
                //"reaches past it)")
            return
        end select
        if (case%solver%xpic) call root%fail(error, 'solver.transfer = "xpic" with ' &
            //'"periodic" faces: the XPIC projection does not tie the faces yet; use "flip", ' &
            //'"apic" or a FLIP-PIC blend')
    end subroutine check_periodic

    !> Whether some body holds particles of each material (its own or a list's).
    pure function materials_used(materials, bodies) result(used)
        type(material_spec_type), intent(in) :: materials(:)
            !! the materials
        type(body_spec_type), allocatable, intent(in) :: bodies(:)
            !! the bodies (unallocated: the particles come from a state file, which may hold
            !! any material)
        logical :: used(size(materials))

        integer :: b

        used = .not. allocated(bodies)
        if (.not. allocated(bodies)) return
        do b = 1, size(bodies)
            if (bodies(b)%material > 0) used(bodies(b)%material) = .true.
            if (allocated(bodies(b)%list)) used(pack(bodies(b)%list%material, &
                bodies(b)%list%material > 0)) = .true.
        end do
    end function materials_used

    !> A case of rigid bodies has a deformable body too: a rigid body limits no time step, and
    !> moves over the material it touches. Rigid bodies need one image (their motion is summed
    !> over all their nodes in the middle of a step).
    subroutine check_deformable(root, case, error)
        type(cursor_type), intent(in) :: root
            !! top-level object
        type(case_type), intent(in) :: case
            !! the case read so far
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        logical :: used(size(case%materials)), rigid(size(case%materials))
        integer :: m

        if (.not. any(case%motions%rigid > 0)) return
        used = materials_used(case%materials, case%bodies)
        do m = 1, size(case%materials)
            rigid(m) = .false.
            if (allocated(case%materials(m)%law)) rigid(m) = case%materials(m)%law%rigid()
        end do
        if (.not. any(used .and. .not. rigid)) then
            call root%fail(error, "every body of the case is rigid; a rigid body moves over " &
                //"the material it touches: give the case a body of a deformable material")
        end if
    end subroutine check_deformable

    !> `name`: default from the file name; it becomes a folder name, so keep it simple.
    subroutine read_name(root, default_name, name, error)
        type(cursor_type), intent(in) :: root
            !! top-level object
        character(len=*), intent(in) :: default_name
            !! name used when the key is absent
        character(len=:), allocatable, intent(out) :: name
            !! the case name
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        character(len=*), parameter :: rule = "use only letters, digits, '-', '_' and '.', " &
            //"not starting with '.' (the name is used as the output folder name)"
        logical :: found

        name = default_name
        call root%get_string("name", name, error, found=found)
        if (allocated(error)) return
        if (len(name) > max_case_name) then
            if (found) then
                call root%fail(error, 'name = "'//name(1:20)//'..." is '// &
                    int_text(len(name))//" bytes long, at most "//int_text(max_case_name) &
                    //" (it names the file <name>.xdmf.tmp of the output folder, and a file "// &
                    "name has at most "//int_text(max_name_bytes)//" bytes)")
            else
                call root%fail(error, 'the case name "'//name(1:20)//'..." taken '// &
                    "from the file name is "//int_text(len(name))//" bytes long, at "// &
                    "most "//int_text(max_case_name)//'; set a shorter "name" in the case file')
            end if
            return
        end if
        if (valid_name(name)) return
        if (found) then
            call root%fail(error, 'name = "'//name//'" is not allowed: '//rule)
        else
            call root%fail(error, 'the case name "'//name//'" taken from the file ' &
                //"name is not allowed: "//rule//'; set "name" in the case file')
        end if
    end subroutine read_name

    !> A case name is safe as a folder name: letters, digits, '-', '_', '.', not leading '.'.
    pure logical function valid_name(name)
        character(len=*), intent(in) :: name
            !! case name

        character(len=*), parameter :: allowed = "abcdefghijklmnopqrstuvwxyz" &
            //"ABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789-_."

        valid_name = len(name) > 0
        if (.not. valid_name) return
        valid_name = name(1:1) /= "." .and. verify(name, allowed) == 0
    end function valid_name

end submodule mpm_case_reader
